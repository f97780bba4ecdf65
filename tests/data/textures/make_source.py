#!/usr/bin/env python3
"""Writes source.png, the image every compressed texture of this folder is made from, and
source.glb, a unit quad showing it as base colour (its PNG in a bufferView), the input of
glTF-Transform's webp command (make_textures.sh). With a folder as argument, also writes there
tiny.png (an 8x8 crop) and tiny-alpha.png (the crop with an alpha gradient), the sources of the
fuzz seeds.

The image is 128x128 RGB and made here, so that the folder holds no one else's picture: smooth
gradients (what lossy codecs keep best), hard-edged discs and stripes (what they blur and ring
on), and a fine checker (what ETC1S's block endpoints lose), all deterministic.
"""
import json
import math
import struct
import sys
import zlib

SIZE = 128


def pixel(x, y):
    u, v = (x + 0.5) / SIZE, (y + 0.5) / SIZE
    r = 40 + 180 * u
    g = 60 + 160 * v
    b = 120 + 100 * math.sin(6.0 * u + 3.0 * v)
    for cx, cy, radius, colour in ((0.3, 0.3, 0.18, (230, 40, 40)),
                                   (0.7, 0.6, 0.22, (30, 200, 90)),
                                   (0.35, 0.78, 0.12, (250, 230, 60))):
        if (u - cx) ** 2 + (v - cy) ** 2 < radius ** 2:
            r, g, b = colour
    if 0.55 < u < 0.95 and 0.08 < v < 0.3 and int(u * 40) % 2 == 0:
        r, g, b = 20, 20, 30
    if u < 0.25 and v > 0.88 and (x // 2 + y // 2) % 2 == 0:
        r, g, b = 255, 255, 255
    return tuple(max(0, min(255, int(round(c)))) for c in (r, g, b))


def png(width, height, rows, channels=3):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))
    raw = b"".join(b"\0" + bytes(row) for row in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2 if channels == 3 else 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def glb(image):
    # A unit quad in the xy plane facing +z, uv (0,0) at its top left, as glTF's uv are.
    positions = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
    normals = struct.pack("<12f", *([0, 0, 1] * 4))
    uv = struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0)
    indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0"
    parts = [positions, normals, uv, indices, image]
    views, bin_ = [], b""
    for part in parts:
        views.append({"buffer": 0, "byteOffset": len(bin_), "byteLength": len(part)})
        bin_ += part + b"\0" * (-len(part) % 4)
    views[3]["byteLength"] = 12
    doc = {
        "asset": {"version": "2.0", "generator": "oer tests/data/textures/make_source.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                     "indices": 3, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                "metallicFactor": 0}}],
        "textures": [{"source": 0}],
        "images": [{"bufferView": 4, "mimeType": "image/png"}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "bufferViews": views,
        "buffers": [{"byteLength": len(bin_)}],
    }
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(bin_)
    return (struct.pack("<4sII", b"glTF", 2, total) + struct.pack("<I4s", len(text), b"JSON") + text
            + struct.pack("<I4s", len(bin_), b"BIN\0") + bin_)


rows = [[c for x in range(SIZE) for c in pixel(x, y)] for y in range(SIZE)]
image = png(SIZE, SIZE, rows)
with open("source.png", "wb") as f:
    f.write(image)
with open("source.glb", "wb") as f:
    f.write(glb(image))
if len(sys.argv) > 1:
    crop = [row[28 * 3:36 * 3] for row in rows[28:36]]
    with open(sys.argv[1] + "/tiny.png", "wb") as f:
        f.write(png(8, 8, crop))
    alpha = [[c for x in range(8) for c in (*row[3 * x:3 * x + 3], 32 * x + 16)] for row in crop]
    with open(sys.argv[1] + "/tiny-alpha.png", "wb") as f:
        f.write(png(8, 8, alpha, channels=4))
