#!/usr/bin/env python3
"""Writes a UV sphere of 2 * NU * NV triangles as OBJ with its .mtl (a colour texture and a normal map), with the
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
