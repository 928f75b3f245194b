#pragma once

namespace orbis {

/// Where a volume lies relative to a plane or a frustum.
///
/// Against a Plane: Inside is wholly on the side the normal points to, Outside wholly on the
/// other side, Intersecting crossing or touching the plane. Against a Frustum: Inside is inside
/// every plane, Outside is outside at least one, Intersecting otherwise (conservative: a volume
/// near a frustum corner may be reported Intersecting although it lies outside).
enum class Intersect { Outside, Intersecting, Inside };

} // namespace orbis
