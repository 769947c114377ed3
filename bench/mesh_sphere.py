#!/usr/bin/env python3
"""Writes a UV sphere of 2 * NU * NV triangles as OBJ with its .mtl (a colour texture and a normal map) and as GLB, with the
sphere shape's (u, v): u the longitude from +x (0.25 at -z), v the latitude. Usage: mesh_sphere.py DIR [NU NV]."""
import math
import sys

out = sys.argv[1]
nu, nv = (int(sys.argv[2]), int(sys.argv[3])) if len(sys.argv) > 3 else (1000, 500)
with open(f"{out}/sphere.obj", "w") as o:
    o.write("mtllib sphere.mtl\n")
    rows = [(math.cos(math.pi * (j / nv - 0.5)), math.sin(math.pi * (j / nv - 0.5))) for j in range(nv + 1)]
    cols = [(math.cos(2 * math.pi * i / nu), math.sin(2 * math.pi * i / nu)) for i in range(nu + 1)]
    for c, s in rows:
        o.writelines(f"v {c * x:.6f} {s:.6f} {-c * z:.6f}\n" for x, z in cols)
    for j in range(nv + 1):
        o.writelines(f"vt {i / nu:.6f} {j / nv:.6f}\n" for i in range(nu + 1))
    for c, s in rows:
        o.writelines(f"vn {c * x:.6f} {s:.6f} {-c * z:.6f}\n" for x, z in cols)
    o.write("usemtl m\n")
    for j in range(nv):
        for i in range(nu):
            a = j * (nu + 1) + i + 1
            b, c, d = a + 1, a + nu + 2, a + nu + 1
            o.write(f"f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}\nf {a}/{a}/{a} {c}/{c}/{c} {d}/{d}/{d}\n")
with open(f"{out}/sphere.mtl", "w") as o:
    o.write("newmtl m\nKd 1 1 1\nKs 0.3 0.3 0.3\nNs 40\nmap_Kd bricks_color.png\nnorm bricks_normal.png\n")

# The same sphere as one GLB (glTF 2.0 binary: positions, normals, TEXCOORD_0 with glTF's v down, 32-bit
# indices; the same two textures by URI, no tangents, so MikkTSpace makes them as for the OBJ).
import array
import json
import struct

positions, normals, uvs = array.array("f"), array.array("f"), array.array("f")
for j, (c, s) in enumerate(rows):
    for i, (x, z) in enumerate(cols):
        positions.extend((c * x, s, -c * z))
        normals.extend((c * x, s, -c * z))
        uvs.extend((i / nu, 1.0 - j / nv))
indices = array.array("I")
for j in range(nv):
    for i in range(nu):
        a = j * (nu + 1) + i
        b, c, d = a + 1, a + nu + 2, a + nu + 1
        indices.extend((a, b, c, a, c, d))
blobs = [positions.tobytes(), normals.tobytes(), uvs.tobytes(), indices.tobytes()]
offsets = [sum(len(b) for b in blobs[:k]) for k in range(4)]
count = (nu + 1) * (nv + 1)
gltf = {
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "buffers": [{"byteLength": sum(len(b) for b in blobs)}],
    "bufferViews": [
        {"buffer": 0, "byteOffset": offsets[k], "byteLength": len(blobs[k]), "target": 34963 if k == 3 else 34962}
        for k in range(4)
    ],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3", "min": [-1, -1, -1], "max": [1, 1, 1]},
        {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": count, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
    ],
    "images": [{"uri": "bricks_color.png"}, {"uri": "bricks_normal.png"}],
    "textures": [{"source": 0}, {"source": 1}],
    "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "normalTexture": {"index": 1}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
}
text = json.dumps(gltf).encode()
text += b" " * (-len(text) % 4)
binary = b"".join(blobs)
with open(f"{out}/sphere.glb", "wb") as o:
    o.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(binary)))
    o.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
    o.write(struct.pack("<II", len(binary), 0x004E4942) + binary)
