#!/usr/bin/python3
"""Stands a glTF binary converted from glmark2's 3ds meshes upright.

    upright_glb.py IN.glb OUT.glb

assimp's 3ds importer assumes 3ds's Z-up axes and converts them to glTF's Y-up with a matrix on
the root node (<3DSDummyRoot>: y -> -z, z -> y). glmark2's horse and cat are authored Y-up
(glmark2 draws them without a rotation), so that matrix lays them on their side: this removes
it and leaves every other byte as assimp wrote it. Any other root transform is refused (exit 1)
rather than dropped, since it would be the model's own.
"""

import json
import struct
import sys
from pathlib import Path

GLB_MAGIC = 0x46546C67  # "glTF"
JSON_CHUNK = 0x4E4F534A  # "JSON"
HEADER = struct.Struct("<III")  # magic, version, total length (glTF 2.0 section 4.4)
CHUNK_HEADER = struct.Struct("<II")  # chunk length, chunk type
# Column-major, as glTF stores it: the columns are x -> x, y -> -z, z -> y.
Z_UP_TO_Y_UP = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]


class GlbError(Exception):
    """The input is not a glTF binary of the shape assimp writes from a 3ds file."""


def split_glb(data: bytes, name: str) -> tuple[dict, bytes]:
    """The JSON chunk, parsed, and the bytes after it (the BIN chunk, untouched)."""
    magic, version, length = HEADER.unpack_from(data, 0)
    if magic != GLB_MAGIC or version != 2 or length != len(data):
        raise GlbError(f"{name}: not a glTF 2.0 binary of {len(data)} bytes")
    chunk_length, chunk_type = CHUNK_HEADER.unpack_from(data, HEADER.size)
    if chunk_type != JSON_CHUNK:
        raise GlbError(f"{name}: the first chunk is not JSON")
    start = HEADER.size + CHUNK_HEADER.size
    return json.loads(data[start:start + chunk_length]), data[start + chunk_length:]


def join_glb(document: dict, rest: bytes) -> bytes:
    """A glTF binary of `document` and the chunks after it; the JSON padded with spaces to 4
    bytes, as the specification requires."""
    text = json.dumps(document, separators=(",", ":")).encode("utf-8")
    text += b" " * (-len(text) % 4)
    total = HEADER.size + CHUNK_HEADER.size + len(text) + len(rest)
    return (HEADER.pack(GLB_MAGIC, 2, total) + CHUNK_HEADER.pack(len(text), JSON_CHUNK) + text
            + rest)


def drop_axis_conversion(document: dict, name: str) -> None:
    """Removes the importer's Z-up to Y-up matrix from every root node of the default scene."""
    scene = document["scenes"][document.get("scene", 0)]
    for index in scene["nodes"]:
        node = document["nodes"][index]
        if node.get("matrix") != Z_UP_TO_Y_UP:
            raise GlbError(f"{name}: root node {index} ({node.get('name', 'unnamed')}) has "
                           f"matrix {node.get('matrix')}, not assimp's 3ds axis conversion")
        del node["matrix"]


def main(argv: list[str]) -> int:
    """Reads IN.glb, writes OUT.glb; a file of another shape is one line on stderr, exit 1."""
    if len(argv) != 2:
        print(__doc__.split("\n\n")[1].strip(), file=sys.stderr)
        return 2
    source, target = Path(argv[0]), Path(argv[1])
    try:
        document, rest = split_glb(source.read_bytes(), str(source))
        drop_axis_conversion(document, str(source))
    except (GlbError, OSError, KeyError, struct.error, json.JSONDecodeError) as error:
        print(f"upright_glb.py: {error}", file=sys.stderr)
        return 1
    target.write_bytes(join_glb(document, rest))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
