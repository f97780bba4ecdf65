#!/usr/bin/env python3
"""Writes the seeds of fuzz_gltf into gltf/: small glTF 2.0 assets (a few hundred bytes to a
few KiB), each using features the loader reads differently: .gltf with data: URIs and .glb,
indexed and not, every index and component type, interleaved (byteStride) and normalised
attributes, a sparse accessor, a node hierarchy with matrices and TRS, materials with each
texture (an embedded 2x2 PNG), KHR_texture_transform and the emissive strength extension.
Run from anywhere: python3 make_gltf_seeds.py"""
import base64
import json
import os
import struct
import zlib

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "gltf")
FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as out:
        out.write(data)


def png_2x2():
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    rows = b"\0" + bytes([255, 0, 0, 255, 0, 255, 0, 255]) + b"\0" + bytes([0, 0, 255, 255] * 2)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def data_uri(data, media="application/octet-stream"):
    return "data:%s;base64,%s" % (media, base64.b64encode(data).decode())


def pad4(data, fill=b"\0"):
    return data + fill * (-len(data) % 4)


class Buffer:
    """One buffer built view by view."""

    def __init__(self):
        self.data = b""
        self.views = []
        self.accessors = []

    def view(self, data, **extra):
        self.data = pad4(self.data)
        self.views.append(dict(buffer=0, byteOffset=len(self.data), byteLength=len(data), **extra))
        self.data += data
        return len(self.views) - 1

    def accessor(self, view, component, count, kind, **extra):
        self.accessors.append(dict(bufferView=view, componentType=component, count=count,
                                   type=kind, **extra))
        return len(self.accessors) - 1


def floats(values):
    return struct.pack("<%df" % len(values), *values)


def quad(buffer, index_type=USHORT):
    positions = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]
    p = buffer.accessor(buffer.view(floats(positions)), FLOAT, 4, "VEC3",
                        min=[0, 0, 0], max=[1, 1, 0])
    n = buffer.accessor(buffer.view(floats([0, 0, 1] * 4)), FLOAT, 4, "VEC3")
    t = buffer.accessor(buffer.view(floats([0, 1, 1, 1, 1, 0, 0, 0])), FLOAT, 4, "VEC2")
    fmt = {UBYTE: "B", USHORT: "H", UINT: "I"}[index_type]
    i = buffer.accessor(buffer.view(struct.pack("<6" + fmt, 0, 1, 2, 0, 2, 3)), index_type, 6,
                        "SCALAR")
    return {"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": t}, "indices": i}


def document(buffer, meshes, nodes=None, materials=None, textures=None, extra=None):
    doc = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": len(buffer.data)}],
           "bufferViews": buffer.views, "accessors": buffer.accessors, "meshes": meshes,
           "nodes": nodes or [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
    if materials:
        doc["materials"] = materials
    if textures:
        doc.update(textures)
    if extra:
        doc.update(extra)
    return doc


def as_gltf(doc, buffer):
    doc["buffers"][0]["uri"] = data_uri(buffer.data)
    return json.dumps(doc, separators=(",", ":")).encode() + b"\n"


def as_glb(doc, buffer):
    text = pad4(json.dumps(doc, separators=(",", ":")).encode(), b" ")
    binary = pad4(buffer.data)
    body = (struct.pack("<II", len(text), 0x4E4F534A) + text
            + struct.pack("<II", len(binary), 0x004E4942) + binary)
    return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body


# A triangle without indices, positions only (normals computed).
buffer = Buffer()
p = buffer.accessor(buffer.view(floats([0, 0, 0, 1, 0, 0, 0, 1, 0])), FLOAT, 3, "VEC3",
                    min=[0, 0, 0], max=[1, 1, 0])
write("triangle.gltf", as_gltf(document(buffer, [{"primitives": [{"attributes": {"POSITION": p}}]}]),
                               buffer))

# Quads with each index type, in .glb.
for index_type, name in ((UBYTE, "ubyte"), (USHORT, "ushort"), (UINT, "uint")):
    buffer = Buffer()
    write("quad-%s.glb" % name, as_glb(document(buffer, [{"primitives": [quad(buffer, index_type)]}]),
                                       buffer))

# Interleaved positions and normalised unsigned-short texture coordinates (byteStride 16).
buffer = Buffer()
interleaved = b"".join(floats(xyz) + struct.pack("<HH", u, v) for xyz, (u, v) in
                       (([0, 0, 0], (0, 0)), ([1, 0, 0], (65535, 0)), ([0, 1, 0], (0, 65535))))
view = buffer.view(interleaved, byteStride=16)
p = buffer.accessor(view, FLOAT, 3, "VEC3", min=[0, 0, 0], max=[1, 1, 0])
t = buffer.accessor(view, USHORT, 3, "VEC2", byteOffset=12, normalized=True)
write("interleaved.gltf", as_gltf(document(buffer, [{"primitives": [
    {"attributes": {"POSITION": p, "TEXCOORD_0": t}}]}]), buffer))

# A sparse accessor: the second vertex of a triangle moved by a sparse substitution.
buffer = Buffer()
base = buffer.view(floats([0, 0, 0, 1, 0, 0, 0, 1, 0]))
sparse_indices = buffer.view(struct.pack("<H", 1))
sparse_values = buffer.view(floats([2, 0, 0]))
p = buffer.accessor(base, FLOAT, 3, "VEC3", min=[0, 0, 0], max=[2, 1, 0],
                    sparse={"count": 1, "indices": {"bufferView": sparse_indices,
                                                    "componentType": USHORT},
                            "values": {"bufferView": sparse_values}})
write("sparse.gltf", as_gltf(document(buffer, [{"primitives": [{"attributes": {"POSITION": p}}]}]),
                             buffer))

# A hierarchy: a matrix node, a TRS child, two meshes, one instanced twice.
buffer = Buffer()
meshes = [{"primitives": [quad(buffer)]}, {"primitives": [quad(buffer, UBYTE)]}]
nodes = [{"children": [1, 2], "matrix": [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 1, 0, 1]},
         {"mesh": 0, "translation": [1, 0, 0], "rotation": [0, 0.7071068, 0, 0.7071068],
          "scale": [1, 0.5, 1]},
         {"mesh": 1, "children": [3]}, {"mesh": 0, "translation": [0, 0, -2]}]
write("hierarchy.glb", as_glb(document(buffer, meshes, nodes), buffer))

# Materials: a textured metallic-roughness material with every texture (a normal texture makes
# the loader generate tangents), KHR_texture_transform, emissive strength, alpha mask and blend.
buffer = Buffer()
image_view = buffer.view(png_2x2())
textured = quad(buffer)
textured["material"] = 0
second = quad(buffer)
second["material"] = 1
materials = [
    {"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.5, 1],
                              "baseColorTexture": {"index": 0, "extensions": {
                                  "KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2],
                                                            "rotation": 0.3}}},
                              "metallicFactor": 0.2, "roughnessFactor": 0.6,
                              "metallicRoughnessTexture": {"index": 0}},
     "normalTexture": {"index": 0, "scale": 0.8}, "occlusionTexture": {"index": 0},
     "emissiveTexture": {"index": 0}, "emissiveFactor": [1, 0.5, 0],
     "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
     "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": True},
    {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 1, 0.5]}, "alphaMode": "BLEND"},
]
textures = {"images": [{"bufferView": image_view, "mimeType": "image/png"}],
            "samplers": [{"magFilter": 9728, "minFilter": 9987, "wrapS": 33648, "wrapT": 33071}],
            "textures": [{"source": 0, "sampler": 0}]}
extensions = {"extensionsUsed": ["KHR_texture_transform", "KHR_materials_emissive_strength"]}
doc = document(buffer, [{"primitives": [textured, second]}], materials=materials, textures=textures,
               extra=extensions)
write("materials.glb", as_glb(doc, buffer))
