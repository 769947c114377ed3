#!/usr/bin/env python3
"""The peer of bench/mesh.sh: the same 1M-triangle UV sphere (bench/mesh_sphere.py's vertices, uv and normals,
its analytic tangents), the same colour texture (sRGB) and normal map (linear), both trilinear, the same camera
and two directional lights with Blinn-Phong, rendered by Mesa's llvmpipe (OpenGL 4.5 through EGL, moderngl) into
a 1920x1080 framebuffer with back faces culled. Prints the median frame time (glFinish after each frame).

Usage: llvmpipe_mesh.py DIR_WITH_TEXTURES [FRAMES]   (needs: pip install moderngl numpy pillow)
"""
import statistics
import sys
import time

import moderngl
import numpy as np
from PIL import Image

folder = sys.argv[1]
frames = int(sys.argv[2]) if len(sys.argv) > 2 else 9
nu, nv = 1000, 500
W, H = 1920, 1080

# The vertices of bench/mesh_sphere.py: u the longitude from +x (0.25 at -z), v the latitude.
u = np.arange(nu + 1) / nu
v = np.arange(nv + 1) / nv
phi, theta = np.meshgrid(2 * np.pi * u, np.pi * (v - 0.5))
c, s = np.cos(theta), np.sin(theta)
pos = np.stack([c * np.cos(phi), s, -c * np.sin(phi)], -1).reshape(-1, 3)
uv = np.stack(np.meshgrid(u, v), -1).reshape(-1, 2)
tangent = np.stack([-np.sin(phi), np.zeros_like(phi), -np.cos(phi)], -1).reshape(-1, 3)
vertices = np.concatenate([pos, pos, uv, tangent], 1).astype("f4")
a = (np.arange(nv)[:, None] * (nu + 1) + np.arange(nu)[None, :]).reshape(-1)
b, cc, d = a + 1, a + nu + 2, a + nu + 1
indices = np.stack([a, b, cc, a, cc, d], 1).astype("i4").reshape(-1)

ctx = moderngl.create_standalone_context(backend="egl")
renderer = ctx.info["GL_RENDERER"]
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
void main() {
    vec3 N = normalize(n);
    vec3 T = normalize(tg - N * dot(N, tg));
    vec3 B = cross(N, T);
    vec3 m = texture(normals, t).rgb * 2.0 - 1.0;
    vec3 nn = normalize(T * m.x + B * m.y + N * m.z);
    vec3 albedo = texture(colour, t).rgb;
    vec3 V = normalize(eye - p);
    vec3 dirs[2] = vec3[2](normalize(vec3(0.5, 0.5, 1.0)), normalize(vec3(-0.6, -0.3, 1.0)));
    float k[2] = float[2](1.0, 0.4);
    vec3 c = vec3(0.0);
    for (int i = 0; i < 2; i++) {
        float ndl = dot(nn, dirs[i]);
        if (ndl > 0.0) {
            float ndh = max(dot(nn, normalize(dirs[i] + V)), 0.0);
            c += k[i] * (albedo * ndl + vec3(0.3 * pow(ndh, 40.0)));
        }
    }
    frag = vec4(pow(c, vec3(1.0 / 2.2)), 1.0);
}
""",
)
vbo = ctx.buffer(vertices.tobytes())
ibo = ctx.buffer(indices.tobytes())
vao = ctx.vertex_array(prog, [(vbo, "3f 3f 2f 3f", "in_pos", "in_normal", "in_uv", "in_tangent")], ibo)


def texture(name, srgb):
    img = Image.open(f"{folder}/{name}").convert("RGBA").transpose(Image.FLIP_TOP_BOTTOM)
    tex = ctx.texture(img.size, 4, img.tobytes(), internal_format=0x8C43 if srgb else None)
    tex.build_mipmaps()
    tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    return tex


texture("bricks_color.png", True).use(0)
texture("bricks_normal.png", False).use(1)
prog["colour"] = 0
prog["normals"] = 1
prog["eye"] = (0.0, 0.0, 4.0)
f = 1.0 / np.tan(np.radians(40.0) / 2)
near, far = 0.1, 10.0
proj = np.array(
    [[f * H / W, 0, 0, 0], [0, f, 0, 0], [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]]
)
view = np.eye(4)
view[2, 3] = -4.0
prog["mvp"].write((proj @ view).T.astype("f4").tobytes())
fbo = ctx.simple_framebuffer((W, H), components=4)
fbo.use()
ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
times = []
for k in range(frames + 1):
    start = time.perf_counter()
    fbo.clear(0.0, 0.0, 0.0, 1.0)
    vao.render()
    ctx.finish()
    if k > 0:
        times.append((time.perf_counter() - start) * 1e3)
print(f"llvmpipe median_ms={statistics.median(times):.2f} min_ms={min(times):.2f} frames={frames} renderer={renderer!r}")
