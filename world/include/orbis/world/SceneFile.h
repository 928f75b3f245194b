#pragma once

#include "orbis/world/CameraKeyframe.h"
#include "orbis/world/Diagnostics.h"
#include "orbis/world/SceneDescription.h"

#include <orbis/core/Error.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::world {

/// The newest scene-file version this build reads (it reads every one before too); files with a
/// higher "version" are refused. Version 2 (this build) depth-tests billboards and labels by
/// default; a version 1 file is read as it was written: they are never depth-tested unless it says
/// otherwise (docs/scene-format.md, "Versions").
inline constexpr int kSceneFileVersion = 2;
/// The newest camera-path file version this build reads.
inline constexpr int kCameraPathVersion = 1;

/// A scene file that cannot be read, is not JSON, or says something invalid. what() is
/// "origin:line:column: /json/pointer: reason", line and column omitted when unknown (0) and the
/// pointer omitted for errors that are not about one value (unreadable file, invalid JSON).
class SceneFileError : public Error {
public:
    SceneFileError(std::string origin, std::string pointer, std::size_t line, std::size_t column,
                   std::string reason);

    /// The file name as the caller gave it, or the origin name passed to parseSceneText.
    const std::string& origin() const noexcept { return _origin; }
    /// JSON pointer (RFC 6901) of the offending key or value: "" for the whole document, and
    /// for errors that are not about one value.
    const std::string& pointer() const noexcept { return _pointer; }
    /// 1-based line and column (in characters) of the offending key or value; 0 when unknown.
    std::size_t line() const noexcept { return _line; }
    std::size_t column() const noexcept { return _column; }
    /// What is wrong, without the location.
    const std::string& reason() const noexcept { return _reason; }

private:
    std::string _origin;
    std::string _pointer;
    std::size_t _line;
    std::size_t _column;
    std::string _reason;
};

struct SceneParseOptions {
    /// Check that every file the scene names exists (and that a CSV source has lon and lat
    /// columns). Off: paths are only resolved, and a texture is a TMS folder when the path has
    /// no extension.
    bool checkFiles = true;
    /// Where faults go when the caller wants every one: set, parsing records each fault here and
    /// reads on past it (the description returned holds what could be read) instead of throwing
    /// at the first. Not owned.
    DiagnosticList* diagnostics = nullptr;
};

/// Reads and validates a scene file; relative paths in it resolve against the file's folder.
/// Throws SceneFileError naming the file, the JSON pointer, the line and the column.
SceneDescription parseSceneFile(const std::filesystem::path& path, const SceneParseOptions& options = {});

/// Parses scene-file text. originName names it in messages; relative paths resolve against
/// baseDirectory (made absolute against the current directory if relative). Throws SceneFileError.
SceneDescription parseSceneText(std::string_view text, std::string_view originName,
                                const std::filesystem::path& baseDirectory, const SceneParseOptions& options = {});

/// Reads a camera path file for `orbis render --path` (docs/scene-format.md): {"version": 1,
/// "keyframes": [{"time": s, "position": {lon, lat, height}, "target": {...}}, ...]}, at least two
/// keyframes in increasing time. Throws SceneFileError like parseSceneFile.
std::vector<CameraKeyframe> parseCameraPathFile(const std::filesystem::path& path);
std::vector<CameraKeyframe> parseCameraPathText(std::string_view text, std::string_view originName);

/// The text of data/scenes/default.json, embedded in the library at build time.
std::string_view defaultSceneText() noexcept;

/// The built-in default scene (defaultSceneText parsed, origin "<default scene>"). Its relative
/// paths resolve against scenesDirectory, as data/scenes/default.json's own do against its folder:
/// pass the scenes/ folder of the data the program uses (the source tree's data/, or the
/// installed one). Throws SceneFileError when a file it names is missing.
SceneDescription parseDefaultScene(const std::filesystem::path& scenesDirectory,
                                   const SceneParseOptions& options = {});

} // namespace orbis::world
