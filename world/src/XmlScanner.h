#pragma once

// A small, bounded XML reader for service descriptions (tilemapresource.xml and the like): one
// linear pass without recursion, limits on size, depth, elements and attributes checked as it goes,
// no DTDs and no entities beyond XML's five and character references, so no input can overflow the
// stack, expand, or run long. Private to orbis::world.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace orbis::world::detail {

struct XmlElement {
    std::string name;
    std::vector<std::pair<std::string, std::string>> attributes; ///< entities resolved, in file order
    std::string text;         ///< character data directly inside (CDATA included), entities resolved
    int parent = -1;          ///< index in XmlDocument::elements; -1 for the root
    std::vector<int> children;
    int line = 0;             ///< where the start tag is, for messages

    /// The value of an attribute; empty when absent.
    std::optional<std::string_view> attribute(std::string_view attributeName) const noexcept;
};

struct XmlLimits {
    std::size_t maximumBytes = std::size_t{1} << 20;
    int maximumDepth = 32;
    std::size_t maximumElements = 20000;
    std::size_t maximumAttributes = 32; ///< per element
};

struct XmlDocument {
    std::vector<XmlElement> elements; ///< elements[0] is the root, then the others in document order

    const XmlElement& root() const { return elements.front(); }
    /// The first child of `element` named `name`; null when there is none.
    const XmlElement* child(const XmlElement& element, std::string_view name) const noexcept;
    /// Every child of `element` named `name`, in order.
    std::vector<const XmlElement*> children(const XmlElement& element, std::string_view name) const;
};

/// Parses a whole document. Throws orbis::Error "NAME:LINE:COLUMN: what" for malformed XML, a
/// DOCTYPE with declarations, a NUL byte, an unknown entity, or any limit passed.
XmlDocument parseXml(std::string_view text, std::string_view nameForMessages, const XmlLimits& limits = {});

/// Text with & < > " escaped for an attribute value or element content.
std::string escapeXml(std::string_view text);

} // namespace orbis::world::detail
