#!/usr/bin/env python3
"""Seeds of fuzz_gltf_meshopt and fuzz_gltf_draco (tests/fuzz/README.md), cut from real files.

    python3 make_compressed_seeds.py GLB_OR_GLTF...

Each EXT_meshopt_compression bufferView of the files becomes a gltf_meshopt/ seed (mode, filter,
byteStride and count, then the compressed bytes) and each KHR_draco_mesh_compression stream a
gltf_draco/ seed (the POSITION and indices accessors' counts, the order of the attribute ids,
then the stream), up to 16 KiB each (fuzz.sh's -max_len), at most 6 of each kind per file. The
committed seeds come from 2CylinderEngine of assimp-testmodels: its Draco sample
(glTF2/draco/2CylinderEngine.gltf), and its .glb through `gltfpack -cc`, `gltf-transform meshopt`
and `gltf-transform draco` (tests/mesh/compressed_gltf_tools_test.cpp makes the same files).
Their index views are too large for a seed, so gltf_meshopt/grid-*.bin are a 7 x 7 quad grid's
indices (TRIANGLES of 2 and 4 bytes, INDICES of 4) encoded by meshoptimizer's own JavaScript
encoder (MeshoptEncoder.encodeGltfBuffer, in tests/mesh/gltf_tools/node_modules), headed alike.
"""
import json
import pathlib
import struct
import sys

HERE = pathlib.Path(__file__).parent
MODES = {"ATTRIBUTES": 0, "TRIANGLES": 1, "INDICES": 2}
FILTERS = {"NONE": 0, "OCTAHEDRAL": 1, "QUATERNION": 2, "EXPONENTIAL": 3}
LIMIT = 16384


def load(path):
    data = path.read_bytes()
    if data[:4] == b"glTF":
        length = struct.unpack_from("<I", data, 12)[0]
        document = json.loads(data[20:20 + length])
        rest = data[20 + length:]
        buffers = [rest[8:8 + struct.unpack_from("<I", rest, 0)[0]]] if rest else []
        return document, buffers
    document = json.loads(data)
    return document, [(path.parent / b["uri"]).read_bytes() for b in document["buffers"]]


def main():
    for name in sys.argv[1:]:
        path = pathlib.Path(name)
        document, buffers = load(path)
        stem = path.stem
        made = 0
        for index, view in enumerate(document.get("bufferViews", [])):
            meshopt = view.get("extensions", {}).get("EXT_meshopt_compression")
            if meshopt is None or made >= 6 or meshopt["byteLength"] + 7 > LIMIT:
                continue
            start = meshopt.get("byteOffset", 0)
            data = buffers[meshopt["buffer"]][start:start + meshopt["byteLength"]]
            header = bytes([MODES[meshopt["mode"]], FILTERS[meshopt.get("filter", "NONE")],
                            meshopt["byteStride"]]) + struct.pack("<I", meshopt["count"])
            out = HERE / "gltf_meshopt" / f"{stem}-view{index}.bin"
            out.write_bytes(header + data)
            made += 1
        made = 0
        for mesh in document.get("meshes", []):
            for primitive in mesh["primitives"]:
                draco = primitive.get("extensions", {}).get("KHR_draco_mesh_compression")
                if draco is None or made >= 6:
                    continue
                view = document["bufferViews"][draco["bufferView"]]
                start = view.get("byteOffset", 0)
                data = buffers[view["buffer"]][start:start + view["byteLength"]]
                if len(data) + 9 > LIMIT:
                    continue
                points = document["accessors"][primitive["attributes"]["POSITION"]]["count"]
                indices = document["accessors"][primitive["indices"]]["count"]
                reversed_ids = int(draco["attributes"]["POSITION"] != 0)
                header = struct.pack("<II", points, indices) + bytes([reversed_ids])
                out = HERE / "gltf_draco" / f"{stem}-stream{made}.bin"
                out.write_bytes(header + data)
                made += 1


if __name__ == "__main__":
    main()
