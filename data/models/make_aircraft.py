#!/usr/bin/env python3
"""Writes the Orbis test aircraft: aircraft.gltf (+ aircraft.bin, aircraft-paint.png) and aircraft.glb.

Made by the Orbis project for its tests and examples (licence: as the project). Not needed at run
time: the files it writes are committed. Run it from anywhere; it writes next to itself.

The model, in glTF's axes (metres, +y up, +z the front, so +x is the aircraft's left):
  fuselage   tapered box from z = -4.5 (tail) to z = 3.0, painted with a 16x16 texture
             (white, a navy cheat line and a red pinstripe) under a white base colour factor
  nose       yellow pyramid to z = 4.5, non-indexed and without normals (flat-shaded by readers)
  wing       silver slab, span 11 m (x = -5.5 .. 5.5)
  tailplane  the wing's mesh again, node scale (0.35, 1, 0.45) and translation (0, 0.35, -4)
  fin        blue slab drawn flat in x-z, stood up by its node's 90 degree rotation about z
  lights     red box at the left wingtip (+x), green box at the right (-x), as aircraft have;
             one cube's accessors shared by two meshes of different materials, u8 indices
Nodes: one root "aircraft" with a child per part.
"""

import base64
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


# -- geometry ---------------------------------------------------------------------------------------

def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def normalize(a):
    length = math.sqrt(dot(a, a))
    return [c / length for c in a]


class Part:
    """Flat-shaded faces: each face has its own vertices, normal and texture coordinates."""

    def __init__(self):
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def face(self, corners, inside, uv=None):
        """A planar convex polygon, turned so that it is counter-clockwise seen from outside (away
        from the point `inside`)."""
        normal = normalize(cross(sub(corners[1], corners[0]), sub(corners[2], corners[0])))
        centre = [sum(c[i] for c in corners) / len(corners) for i in range(3)]
        if dot(normal, sub(centre, inside)) < 0:
            corners = corners[::-1]
            normal = [-c for c in normal]
        base = len(self.positions)
        for corner in corners:
            self.positions.append(corner)
            self.normals.append(normal)
            self.uvs.append(uv(corner) if uv else [0.0, 0.0])
        for i in range(1, len(corners) - 1):
            self.indices += [base, base + i, base + i + 1]


def prism_xz(polygon, y0, y1):
    """A convex polygon in the x-z plane, extruded from y0 to y1."""
    part = Part()
    inside = [sum(p[0] for p in polygon) / len(polygon), (y0 + y1) / 2, sum(p[1] for p in polygon) / len(polygon)]
    part.face([[x, y0, z] for x, z in polygon], inside)
    part.face([[x, y1, z] for x, z in polygon], inside)
    for i in range(len(polygon)):
        (xa, za), (xb, zb) = polygon[i], polygon[(i + 1) % len(polygon)]
        part.face([[xa, y0, za], [xb, y0, zb], [xb, y1, zb], [xa, y1, za]], inside)
    return part


def fuselage():
    front = {"x": 0.6, "y0": -0.6, "y1": 0.6, "z": 3.0}
    back = {"x": 0.2, "y0": 0.0, "y1": 0.4, "z": -4.5}

    def corner(end, sx, top):
        return [sx * end["x"], end["y1"] if top else end["y0"], end["z"]]

    def side_uv(p):  # u along the length, v down the image from the top of the fuselage
        return [(p[2] - back["z"]) / (front["z"] - back["z"]), (front["y1"] - p[1]) / (front["y1"] - front["y0"])]

    def plan_uv(p):
        return [(p[2] - back["z"]) / (front["z"] - back["z"]), 0.05]  # the white top row

    part = Part()
    inside = [0.0, 0.1, -0.75]
    for sx in (1, -1):
        part.face([corner(front, sx, False), corner(front, sx, True), corner(back, sx, True), corner(back, sx, False)],
                  inside, side_uv)
    for top in (True, False):
        part.face([corner(front, 1, top), corner(front, -1, top), corner(back, -1, top), corner(back, 1, top)],
                  inside, plan_uv)
    part.face([corner(front, s, t) for s, t in ((1, False), (1, True), (-1, True), (-1, False))], inside, plan_uv)
    part.face([corner(back, s, t) for s, t in ((1, False), (1, True), (-1, True), (-1, False))], inside, plan_uv)
    return part


def nose():
    """Four triangles to the tip, as a plain triangle list (no indices, no normals in the file)."""
    apex = [0.0, -0.1, 4.5]
    square = [[0.6, -0.6, 3.0], [0.6, 0.6, 3.0], [-0.6, 0.6, 3.0], [-0.6, -0.6, 3.0]]
    positions = []
    for i in range(4):
        a, b = square[i], square[(i + 1) % 4]
        # Counter-clockwise from outside: a, b, apex turns the right way when the square runs
        # clockwise seen from the tip; check and swap.
        normal = cross(sub(b, a), sub(apex, a))
        if dot(normal, sub(a, [0.0, 0.0, 3.5])) < 0:
            a, b = b, a
        positions += [a, b, apex]
    return positions


WING = [(5.5, 0.4), (0.0, 1.0), (-5.5, 0.4), (-5.5, -0.6), (0.0, -0.8), (5.5, -0.6)]
FIN = [(0.0, -3.3), (0.0, -4.5), (1.5, -4.6), (1.5, -4.1)]  # x becomes the height once stood up


def cube(half):
    part = Part()
    corners = [[sx * half, sy * half, sz * half] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    for axis in range(3):
        for sign in (-1, 1):
            face = [c for c in corners if c[axis] == sign * half]
            a, b, d, c = face  # two of them differ in one coordinate from a: order round the square
            part.face([a, b, c, d], [0.0, 0.0, 0.0])
    return part


# -- texture ----------------------------------------------------------------------------------------

def paint_png():
    """16x16 RGB: white, a navy cheat line (rows 7-9) and a red pinstripe (row 10)."""
    rows = []
    for y in range(16):
        colour = (255, 255, 255)
        if 7 <= y <= 9:
            colour = (20, 30, 110)
        elif y == 10:
            colour = (200, 20, 20)
        rows.append(b"\x00" + bytes(colour) * 16)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", 16, 16, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + \
        chunk(b"IEND", b"")


# -- glTF -------------------------------------------------------------------------------------------

class Writer:
    def __init__(self):
        self.binary = bytearray()
        self.views, self.accessors = [], []

    def view(self, data, target=None):
        while len(self.binary) % 4:
            self.binary.append(0)
        view = {"buffer": 0, "byteOffset": len(self.binary), "byteLength": len(data)}
        if target:
            view["target"] = target
        self.binary += data
        self.views.append(view)
        return len(self.views) - 1

    def floats(self, rows, kind, bounds=False):
        data = b"".join(struct.pack("<%df" % len(r), *r) for r in rows)
        accessor = {"bufferView": self.view(data, 34962), "componentType": 5126, "count": len(rows), "type": kind}
        if bounds:
            accessor["min"] = [min(r[i] for r in rows) for i in range(len(rows[0]))]
            accessor["max"] = [max(r[i] for r in rows) for i in range(len(rows[0]))]
        self.accessors.append(accessor)
        return len(self.accessors) - 1

    def indices(self, values, component):
        code = {"B": 5121, "H": 5123, "I": 5125}[component]
        data = struct.pack("<%d%s" % (len(values), component), *values)
        self.accessors.append({"bufferView": self.view(data, 34963), "componentType": code, "count": len(values),
                               "type": "SCALAR"})
        return len(self.accessors) - 1

    def part(self, part, component="H", uvs=False):
        attributes = {"POSITION": self.floats(part.positions, "VEC3", True),
                      "NORMAL": self.floats(part.normals, "VEC3")}
        if uvs:
            attributes["TEXCOORD_0"] = self.floats(part.uvs, "VEC2")
        return attributes, self.indices(part.indices, component)


def build(image_in_buffer):
    w = Writer()
    fuselage_attributes, fuselage_indices = w.part(fuselage(), uvs=True)
    nose_position = w.floats(nose(), "VEC3", True)
    wing_attributes, wing_indices = w.part(prism_xz(WING, -0.06, 0.06))
    fin_attributes, fin_indices = w.part(prism_xz(FIN, -0.05, 0.05))
    light_attributes, light_indices = w.part(cube(0.15), component="B")
    png = paint_png()
    image = {"name": "paint"}
    if image_in_buffer:
        image.update({"bufferView": w.view(png), "mimeType": "image/png"})
    else:
        image["uri"] = "aircraft-paint.png"

    def colour(name, rgba, texture=None):
        pbr = {"baseColorFactor": rgba, "metallicFactor": 0.0, "roughnessFactor": 0.8}
        if texture is not None:
            pbr["baseColorTexture"] = {"index": texture}
        return {"name": name, "pbrMetallicRoughness": pbr}

    s45 = math.sqrt(0.5)
    gltf = {
        "asset": {"version": "2.0", "generator": "Orbis data/models/make_aircraft.py",
                  "copyright": "Orbis project, licensed as the project"},
        "scene": 0,
        "scenes": [{"name": "aircraft", "nodes": [0]}],
        "nodes": [
            {"name": "aircraft", "children": [1, 2, 3, 4, 5, 6, 7]},
            {"name": "fuselage", "mesh": 0},
            {"name": "nose", "mesh": 1},
            {"name": "wing", "mesh": 2},
            {"name": "tailplane", "mesh": 2, "translation": [0.0, 0.35, -4.0], "scale": [0.35, 1.0, 0.45]},
            {"name": "fin", "mesh": 3, "translation": [0.0, 0.35, 0.0], "rotation": [0.0, 0.0, s45, s45]},
            {"name": "left light", "mesh": 4, "translation": [5.5, 0.0, -0.1]},
            {"name": "right light", "mesh": 5, "translation": [-5.5, 0.0, -0.1]},
        ],
        "meshes": [
            {"name": "fuselage", "primitives": [{"attributes": fuselage_attributes, "indices": fuselage_indices,
                                                 "material": 0}]},
            {"name": "nose", "primitives": [{"attributes": {"POSITION": nose_position}, "material": 1}]},
            {"name": "wing", "primitives": [{"attributes": wing_attributes, "indices": wing_indices, "material": 2}]},
            {"name": "fin", "primitives": [{"attributes": fin_attributes, "indices": fin_indices, "material": 3}]},
            {"name": "left light", "primitives": [{"attributes": light_attributes, "indices": light_indices,
                                                   "material": 4}]},
            {"name": "right light", "primitives": [{"attributes": light_attributes, "indices": light_indices,
                                                    "material": 5}]},
        ],
        "materials": [
            colour("fuselage", [1.0, 1.0, 1.0, 1.0], texture=0),
            colour("nose", [1.0, 0.6, 0.0, 1.0]),
            colour("wing", [0.6, 0.6, 0.65, 1.0]),
            colour("fin", [0.02, 0.06, 0.5, 1.0]),
            colour("left light (red)", [1.0, 0.0, 0.0, 1.0]),
            colour("right light (green)", [0.0, 1.0, 0.0, 1.0]),
        ],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}],
        "images": [image],
        "accessors": w.accessors,
        "bufferViews": w.views,
    }
    while len(w.binary) % 4:
        w.binary.append(0)
    return gltf, bytes(w.binary), png


def main():
    gltf, binary, png = build(image_in_buffer=False)
    gltf["buffers"] = [{"uri": "aircraft.bin", "byteLength": len(binary)}]
    with open(os.path.join(HERE, "aircraft.gltf"), "w", encoding="utf-8") as out:
        json.dump(gltf, out, indent=1)
        out.write("\n")
    with open(os.path.join(HERE, "aircraft.bin"), "wb") as out:
        out.write(binary)
    with open(os.path.join(HERE, "aircraft-paint.png"), "wb") as out:
        out.write(png)

    gltf, binary, _ = build(image_in_buffer=True)
    gltf["buffers"] = [{"byteLength": len(binary)}]
    text = json.dumps(gltf, separators=(",", ":")).encode("utf-8")
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<I", len(text)) + b"JSON" + text + struct.pack("<I", len(binary)) + b"BIN\x00" + binary
    with open(os.path.join(HERE, "aircraft.glb"), "wb") as out:
        out.write(struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks)


if __name__ == "__main__":
    main()
