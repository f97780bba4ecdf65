#!/usr/bin/env python3
"""Writes the hostile files of this folder: small files whose headers claim far more than their
bytes hold (README.md says what each one is). Run from anywhere: python3 make_hostile.py"""
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as out:
        out.write(data)


# Radiance RGBE: a 155-byte file, 8192x8192 claimed; one RLE scanline start (2, 2,
# width) and 50 run packets of 127 pixels each.
def radiance():
    header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 8192\n"
    body = bytes([2, 2, 0x20, 0x00]) + bytes([0x80 + 127, 0]) * 50
    data = header + body
    assert len(data) == 155, len(data)
    write("radiance-8192x8192.hdr", data)


# OpenEXR: single-part scanline files, 8192x4096, three FLOAT channels.
def exr_attribute(name, type_name, value):
    return name.encode() + b"\0" + type_name.encode() + b"\0" + struct.pack("<i", len(value)) + value


def exr_header(compression):
    channels = b""
    for name in (b"B", b"G", b"R"):
        channels += name + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1)  # FLOAT, linear, 1x1
    channels += b"\0"
    window = struct.pack("<iiii", 0, 0, 8191, 4095)
    return (
        struct.pack("<Ii", 20000630, 2)
        + exr_attribute("channels", "chlist", channels)
        + exr_attribute("compression", "compression", bytes([compression]))
        + exr_attribute("dataWindow", "box2i", window)
        + exr_attribute("displayWindow", "box2i", window)
        + exr_attribute("lineOrder", "lineOrder", bytes([0]))
        + exr_attribute("pixelAspectRatio", "float", struct.pack("<f", 1.0))
        + exr_attribute("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
        + exr_attribute("screenWindowWidth", "float", struct.pack("<f", 1.0))
        + b"\0"
    )


def openexr():
    # No compression: a chunk offset table of 4096 entries (32 KiB) claimed, 8 present, and
    # one chunk header.
    header = exr_header(0)
    first_chunk = len(header) + 8 * 8
    table = b"".join(struct.pack("<Q", first_chunk) for _ in range(8))
    chunk = struct.pack("<ii", 0, 8192 * 12)  # scanline 0 and its 96 KiB of pixels: absent
    write("openexr-8192x4096-chunk-table.exr", header + table + chunk)
    # ZIP (16 scanlines a chunk): the whole table of 256 entries, every one pointing at the same
    # chunk of 8 bytes of data, where 1.5 MiB of filtered pixels need 1.5 KiB of deflate at least.
    header = exr_header(3)
    first_chunk = len(header) + 256 * 8
    table = b"".join(struct.pack("<Q", first_chunk) for _ in range(256))
    chunk = struct.pack("<ii", 0, 8) + bytes(8)
    write("openexr-8192x4096-zip-chunks.exr", header + table + chunk)


# PNG: 8192x4096 RGB, 8 bits, with one IDAT of a few bytes (deflate cannot expand beyond
# 1032:1, so 97 KiB at least are needed for the 96 MiB of filtered rows).
def png_chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png():
    ihdr = struct.pack(">IIBBBBB", 8192, 4096, 8, 2, 0, 0, 0)
    idat = zlib.compress(bytes(8192 * 3 + 1) * 4)
    data = (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) + png_chunk(b"IDAT", idat)
            + png_chunk(b"IEND", b""))
    write("png-8192x4096.png", data)


# JPEG, grey 8192x4096 (524288 blocks of 8x8): a Huffman table whose one 1-bit code means "DC
# difference 0", then a few bytes of scan. Progressive (SOF2): libjpeg reads every scan into a
# buffer of the whole image's coefficients (64 MiB here) when decoding starts. Baseline (SOF0):
# the same claim, decoded row by row.
def jpeg(progressive):
    def segment(marker, payload):
        return bytes([0xFF, marker]) + struct.pack(">H", len(payload) + 2) + payload

    quantisation = segment(0xDB, bytes([0]) + bytes([1]) * 64)
    frame = segment(0xC2 if progressive else 0xC0,
                    struct.pack(">BHHB", 8, 4096, 8192, 1) + bytes([1, 0x11, 0]))
    one_code = bytes([1]) + bytes(15) + bytes([0])  # one code of length 1: symbol 0
    tables = segment(0xC4, bytes([0x00]) + one_code)  # DC table 0
    if not progressive:
        tables += segment(0xC4, bytes([0x10]) + one_code)  # AC table 0: the 1-bit code is EOB
    scan = segment(0xDA, bytes([1, 1, 0x00, 0, 0 if progressive else 63, 0]))
    data = b"\xff\xd8" + quantisation + frame + tables + scan + bytes(64) + b"\xff\xd9"
    write("jpeg-%s-8192x4096.jpg" % ("progressive" if progressive else "baseline"), data)


# glTF: a POSITION accessor of 4,000,000 VEC3 floats (48 MB claimed, under the default vertex
# limit of 5,000,000) whose bufferView holds 36 bytes.
def gltf():
    triangle = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    import base64
    document = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(triangle).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4000000,
                       "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    write("gltf-accessor-4000000-vertices.gltf", json.dumps(document, indent=1).encode() + b"\n")


radiance()
openexr()
png()
jpeg(progressive=True)
jpeg(progressive=False)
gltf()
