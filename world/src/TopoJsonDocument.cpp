#include "TopoJsonDocument.h"

#include "orbis/world/FileAccess.h"

#include "orbis/core/Error.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace orbis::world::detail {

namespace {

using Json = nlohmann::json;

class TopologyReader {
public:
    TopologyReader(const Json& topology, const std::string& source, std::vector<std::string>& warnings)
        : _topology(topology), _source(source), _warnings(warnings)
    {
    }

    Json features(std::string_view objectName)
    {
        readTransform();
        readArcs();
        const auto objects = _topology.find("objects");
        if (objects == _topology.end() || !objects->is_object()) {
            fail("objects", "expected an object of named geometries");
        }
        Json collection = {{"type", "FeatureCollection"}, {"features", Json::array()}};
        Json& features = collection["features"];
        bool found = objectName.empty();
        for (const auto& [name, object] : objects->items()) {
            if (!objectName.empty() && name != objectName) {
                continue;
            }
            found = true;
            const std::string at = "objects." + name;
            // Compared as JSON: a "type" that is not a string is not a collection (value() would throw
            // nlohmann's type_error for it, which escaped as a crash).
            const auto type = object.is_object() ? object.find("type") : object.end();
            if (type != object.end() && *type == "GeometryCollection") {
                const auto geometries = object.find("geometries");
                if (geometries == object.end() || !geometries->is_array()) {
                    fail(at + ".geometries", "expected an array of geometries");
                }
                for (std::size_t i = 0; i < geometries->size(); ++i) {
                    features.push_back(feature((*geometries)[i], at + ".geometries[" + std::to_string(i) + "]"));
                }
            } else {
                features.push_back(feature(object, at));
            }
        }
        if (!found) {
            fail("objects", "no object named \"" + cutForMessage(objectName) + "\"");
        }
        return collection;
    }

private:
    [[noreturn]] void fail(const std::string& at, const std::string& what) const
    {
        throw Error(_source + ": " + at + ": " + what);
    }

    double number(const Json& value, const std::string& at) const
    {
        if (!value.is_number()) {
            fail(at, "expected a number");
        }
        const double x = value.get<double>();
        if (!std::isfinite(x)) {
            fail(at, "not a finite number");
        }
        return x;
    }

    void readTransform()
    {
        const auto transform = _topology.find("transform");
        if (transform == _topology.end() || transform->is_null()) {
            return;
        }
        for (const char* key : {"scale", "translate"}) {
            const auto pair = transform->find(key);
            if (pair == transform->end() || !pair->is_array() || pair->size() != 2) {
                fail(std::string("transform.") + key, "expected two numbers");
            }
            double* into = std::string_view(key) == "scale" ? _scale : _translate;
            into[0] = number((*pair)[0], std::string("transform.") + key + "[0]");
            into[1] = number((*pair)[1], std::string("transform.") + key + "[1]");
        }
        _quantized = true;
    }

    /// A position of an arc or a point: [x, y] (more members are ignored), quantized or not.
    Json position(const Json& value, const std::string& at, double& x, double& y, bool delta) const
    {
        if (!value.is_array() || value.size() < 2) {
            fail(at, "expected a position [x, y]");
        }
        const double u = number(value[0], at + "[0]");
        const double v = number(value[1], at + "[1]");
        x = delta ? x + u : u;
        y = delta ? y + v : v;
        return _quantized ? Json::array({x * _scale[0] + _translate[0], y * _scale[1] + _translate[1]})
                          : Json::array({x, y});
    }

    void readArcs()
    {
        const auto arcs = _topology.find("arcs");
        if (arcs == _topology.end() || !arcs->is_array()) {
            fail("arcs", "expected an array of arcs");
        }
        _arcs.reserve(arcs->size());
        for (std::size_t a = 0; a < arcs->size(); ++a) {
            const std::string at = "arcs[" + std::to_string(a) + "]";
            const Json& arc = (*arcs)[a];
            if (!arc.is_array() || arc.empty()) {
                fail(at, "expected an array of positions");
            }
            Json positions = Json::array();
            double x = 0.0;
            double y = 0.0;
            for (std::size_t i = 0; i < arc.size(); ++i) {
                positions.push_back(position(arc[i], at + "[" + std::to_string(i) + "]", x, y, _quantized));
            }
            _arcs.push_back(std::move(positions));
        }
    }

    /// The positions of arcs joined: each arc after the first without its first position.
    Json joined(const Json& indices, const std::string& at) const
    {
        if (!indices.is_array()) {
            fail(at, "expected an array of arc indices");
        }
        Json positions = Json::array();
        for (std::size_t k = 0; k < indices.size(); ++k) {
            const std::string indexAt = at + "[" + std::to_string(k) + "]";
            if (!indices[k].is_number_integer()) {
                fail(indexAt, "expected an arc index (an integer)");
            }
            const std::int64_t index = indices[k].get<std::int64_t>();
            const bool reversed = index < 0;
            const std::int64_t arc = reversed ? ~index : index;
            if (arc < 0 || static_cast<std::uint64_t>(arc) >= _arcs.size()) {
                fail(indexAt, "arc " + std::to_string(index) + " out of range (the topology has " +
                                  std::to_string(_arcs.size()) + " arcs)");
            }
            const Json& points = _arcs[static_cast<std::size_t>(arc)];
            for (std::size_t i = 0; i < points.size(); ++i) {
                const Json& p = points[reversed ? points.size() - 1 - i : i];
                if (i > 0 || positions.empty()) {
                    positions.push_back(p);
                }
            }
        }
        return positions;
    }

    Json geometry(const Json& object, const std::string& at) const
    {
        if (!object.is_object()) {
            fail(at, "expected a geometry object");
        }
        const auto type = object.find("type");
        if (type == object.end() || type->is_null()) {
            return nullptr; // a null geometry: a feature without one
        }
        if (!type->is_string()) {
            fail(at + ".type", "expected a geometry type name");
        }
        const std::string& name = type->get_ref<const std::string&>();
        if (name == "GeometryCollection") {
            const auto geometries = object.find("geometries");
            if (geometries == object.end() || !geometries->is_array()) {
                fail(at + ".geometries", "expected an array of geometries");
            }
            Json list = Json::array();
            for (std::size_t i = 0; i < geometries->size(); ++i) {
                Json g = geometry((*geometries)[i], at + ".geometries[" + std::to_string(i) + "]");
                if (!g.is_null()) {
                    list.push_back(std::move(g));
                }
            }
            return {{"type", name}, {"geometries", std::move(list)}};
        }
        if (name == "Point" || name == "MultiPoint") {
            const auto coordinates = object.find("coordinates");
            if (coordinates == object.end()) {
                fail(at, "missing \"coordinates\" for a " + name);
            }
            double x = 0.0;
            double y = 0.0;
            if (name == "Point") {
                return {{"type", name}, {"coordinates", position(*coordinates, at + ".coordinates", x, y, false)}};
            }
            if (!coordinates->is_array()) {
                fail(at + ".coordinates", "expected an array of positions");
            }
            Json points = Json::array();
            for (std::size_t i = 0; i < coordinates->size(); ++i) {
                points.push_back(position((*coordinates)[i], at + ".coordinates[" + std::to_string(i) + "]", x, y, false));
            }
            return {{"type", name}, {"coordinates", std::move(points)}};
        }
        const auto arcs = object.find("arcs");
        if (arcs == object.end() || !arcs->is_array()) {
            fail(at + ".arcs", "expected an array of arc indices for a " + name);
        }
        const std::string arcsAt = at + ".arcs";
        auto each = [&](const Json& list, const std::string& listAt, auto&& read) {
            Json out = Json::array();
            for (std::size_t i = 0; i < list.size(); ++i) {
                if (!list[i].is_array()) {
                    fail(listAt + "[" + std::to_string(i) + "]", "expected an array");
                }
                out.push_back(read(list[i], listAt + "[" + std::to_string(i) + "]"));
            }
            return out;
        };
        const auto line = [&](const Json& indices, const std::string& where) { return joined(indices, where); };
        // A polygon's rings, without those quantization collapsed (empty when the outer one went).
        const auto rings = [&](const Json& list, const std::string& where) {
            Json kept = Json::array();
            Json all = each(list, where, line);
            for (std::size_t r = 0; r < all.size(); ++r) {
                if (all[r].size() >= 4) {
                    kept.push_back(std::move(all[r]));
                    continue;
                }
                _warnings.push_back(_source + ": " + where + "[" + std::to_string(r) + "]: left out a ring of " +
                                    std::to_string(all[r].size()) + " positions (collapsed by quantization)" +
                                    (r == 0 ? ", and its polygon with it" : ""));
                if (r == 0) {
                    return Json::array();
                }
            }
            return kept;
        };
        if (name == "LineString") {
            return {{"type", name}, {"coordinates", joined(*arcs, arcsAt)}};
        }
        if (name == "MultiLineString") {
            return {{"type", name}, {"coordinates", each(*arcs, arcsAt, line)}};
        }
        if (name == "Polygon") {
            Json kept = rings(*arcs, arcsAt);
            return kept.empty() ? Json(nullptr) : Json{{"type", name}, {"coordinates", std::move(kept)}};
        }
        if (name == "MultiPolygon") {
            Json polygons = Json::array();
            for (Json& polygon : each(*arcs, arcsAt, [&](const Json& list, const std::string& where) { return rings(list, where); })) {
                if (!polygon.empty()) {
                    polygons.push_back(std::move(polygon));
                }
            }
            return polygons.empty() ? Json(nullptr) : Json{{"type", name}, {"coordinates", std::move(polygons)}};
        }
        fail(at + ".type", "unknown geometry type \"" + cutForMessage(name) + "\"");
    }

    Json feature(const Json& object, const std::string& at) const
    {
        Json feature = {{"type", "Feature"}, {"geometry", geometry(object, at)}};
        if (object.is_object()) {
            if (const auto properties = object.find("properties"); properties != object.end()) {
                feature["properties"] = *properties;
            } else {
                feature["properties"] = Json::object();
            }
            if (const auto id = object.find("id"); id != object.end()) {
                feature["id"] = *id;
            }
        }
        return feature;
    }

    const Json& _topology;
    const std::string& _source;
    std::vector<std::string>& _warnings;
    bool _quantized = false;
    double _scale[2] = {1.0, 1.0};
    double _translate[2] = {0.0, 0.0};
    std::vector<Json> _arcs;
};

} // namespace

nlohmann::json topologyToGeoJson(const nlohmann::json& topology, const std::string& source, std::string_view objectName,
                                 std::vector<std::string>& warnings)
{
    return TopologyReader(topology, source, warnings).features(objectName);
}

} // namespace orbis::world::detail
