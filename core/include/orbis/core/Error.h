#pragma once

#include <stdexcept>
#include <string>

namespace orbis {

/// The one base of every exception Orbis throws for bad input (files, users, the GPU driver).
/// The message names the source (file, line, feature, shader) and what was expected.
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

} // namespace orbis
