#!/usr/bin/env python3
"""The peer of bench/mesh.sh: the same 1M-triangle UV sphere (bench/mesh_sphere.py's vertices, uv and normals,
its analytic tangents), the same colour texture (sRGB) and normal map (linear), both trilinear, the same camera
and two directional lights with Blinn-Phong, rendered by Mesa's llvmpipe (OpenGL 4.5 through EGL, moderngl) into
a 1920x1080 framebuffer with back faces culled. Prints the median frame time (glFinish after each frame) and
writes the last frame to OUT.png when given.

Usage: llvmpipe_mesh.py DIR_WITH_TEXTURES [FRAMES [OUT.png]]   (needs: pip install moderngl numpy pillow)
"""
import sys

import numpy as np

from llvmpipe_common import context, mvp, shading_glsl, texture, time_frames, uv_sphere

folder = sys.argv[1]
frames = int(sys.argv[2]) if len(sys.argv) > 2 else 9
out_png = sys.argv[3] if len(sys.argv) > 3 else None

# The vertices of bench/mesh_sphere.py, with the analytic tangent: dP/du's direction (defined at the poles too).
pos, uv, _, _, indices = uv_sphere(1000, 500)
phi = 2 * np.pi * uv[:, 0]
tangent = np.stack([-np.sin(phi), np.zeros_like(phi), -np.cos(phi)], -1)
vertices = np.concatenate([pos, pos, uv, tangent], 1).astype("f4")
ctx, _ = context()
prog = ctx.program(
    vertex_shader="""
#version 330
uniform mat4 mvp;
in vec3 in_pos; in vec3 in_normal; in vec2 in_uv; in vec3 in_tangent;
out vec3 p; out vec3 n; out vec2 t; out vec3 tg;
void main() { p = in_pos; n = in_normal; t = in_uv; tg = in_tangent; gl_Position = mvp * vec4(in_pos, 1.0); }
""",
    fragment_shader="""
#version 330
uniform sampler2D colour; uniform sampler2D normals; uniform vec3 eye;
in vec3 p; in vec3 n; in vec2 t; in vec3 tg;
out vec4 frag;
""" + shading_glsl([((-0.5, -0.5, -1.0), 1.0), ((0.6, 0.3, -1.0), 0.4)], 0.3, 40) + """
void main() {
    vec3 N = normalize(n);
    vec3 T = normalize(tg - N * dot(N, tg));
    vec3 B = cross(N, T);
    vec3 m = texture(normals, t).rgb * 2.0 - 1.0;
    vec3 nn = normalize(T * m.x + B * m.y + N * m.z);
    vec3 albedo = texture(colour, t).rgb;
    frag = vec4(srgb(shade(nn, albedo, normalize(eye - p))), 1.0);
}
""",
)
vbo = ctx.buffer(vertices.tobytes())
ibo = ctx.buffer(indices.tobytes())
vao = ctx.vertex_array(prog, [(vbo, "3f 3f 2f 3f", "in_pos", "in_normal", "in_uv", "in_tangent")], ibo)
texture(ctx, f"{folder}/bricks_color.png", True).use(0)
texture(ctx, f"{folder}/bricks_normal.png", False).use(1)
prog["colour"] = 0
prog["normals"] = 1
prog["eye"] = (0.0, 0.0, 4.0)
prog["mvp"].write(mvp())
time_frames(ctx, vao, frames, out_png)
