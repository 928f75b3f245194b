#pragma once

// The scenes of the chapter 5 and 6 examples (the bench times the chapter 6 one too), and what
// their side-by-side PNGs need: tiles composed into one image, with captions.

#include <orbis/scene/Scene.h>
#include <orbis/scene/VertexTransform.h>
#include <orbis/world/ImageFile.h>

#include <string>
#include <vector>

namespace orbis::examples {

/// Chapter 5: a 1 m checkerboard on the ground at (10 E, 45 N), seen from 2 m straight above, part
/// of a mesh that reaches 200 km away (a polygon's far corner) so that its bounding sphere's centre
/// is 100 km off: every square drawn with `transform`.
void buildJitterScene(scene::Scene& scene, scene::VertexTransform transform);
/// Where the chapter 5 camera looks, and from how far.
glm::dvec3 jitterSceneTarget();
inline constexpr double kJitterSceneEyeDistance = 2.0;

/// Chapter 6: a 16 m aircraft 2,500 m over synthetic mountains near Everest (200 km of terrain in
/// 2.5 km cells, snow 5 m thick on the cells above 2,600 m from 10 km out), the globe beyond, and a satellite
/// 36,000 km away above the horizon; the camera 60 m behind the aircraft. The frame spans about
/// 50 m to 36,000 km: far/near near a million.
void buildDepthScene(scene::Scene& scene);

/// Tiles of equal size side by side, `columns` per row, separated by `gap` pixels of grey.
Image composeTiles(const std::vector<Image>& tiles, int columns, int gap = 4);
/// Writes text into an RGBA image (DejaVu Sans, white with a dark outline so it reads on any
/// background), its top-left corner at x, y; lines split at '\n'. No font, no text.
void drawCaption(Image& image, int x, int y, const std::string& text, float sizePixels = 14.0f);

} // namespace orbis::examples
