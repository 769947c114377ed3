#!/usr/bin/env python3
"""The peer of the canonical scene (bench/canonical/sphere.toml): the unit sphere as a 512 x 256 quad UV mesh
(262,144 triangles) with its (u, v), dP/du and dP/dv per vertex, the brick colour texture (sRGB, trilinear) and
Blinn's bump mapping in the fragment shader: F = 0.004 h(8u, 4v) from the height map (bilinear, no mipmaps, as
the scene's `interp = "bilinear"`), Fu and Fv by central differences of the table, N' = N + (Fu (N x Pv) -
Fv (N x Pu)) / |N|; Blinn-Phong under the scene's two directional lights (intensities 2.6 and 0.8, specular 0.04,
shininess 87), sRGB out; rendered by Mesa's llvmpipe at 1920x1080, 1 spp, or supersampled SS x SS (the frame
rendered SS times as wide and high). Prints the median frame time and writes the last frame.

Usage: llvmpipe_canonical.py CANONICAL_DIR OUT.png [FRAMES [SS]]   (needs: pip install moderngl numpy pillow)
"""
import sys

import moderngl
import numpy as np

from llvmpipe_common import context, mvp, shading_glsl, texture, time_frames, uv_sphere

folder, out_png = sys.argv[1], sys.argv[2]
frames = int(sys.argv[3]) if len(sys.argv) > 3 else 9
supersample = int(sys.argv[4]) if len(sys.argv) > 4 else 1

pos, uv, pu, pv, indices = uv_sphere(512, 256)
vertices = np.concatenate([pos, uv, pu, pv], 1).astype("f4")
ctx, _ = context()
prog = ctx.program(
    vertex_shader="""
#version 330
uniform mat4 mvp;
in vec3 in_pos; in vec2 in_uv; in vec3 in_pu; in vec3 in_pv;
out vec3 p; out vec2 t; out vec3 pu; out vec3 pv;
void main() { p = in_pos; t = in_uv; pu = in_pu; pv = in_pv; gl_Position = mvp * vec4(in_pos, 1.0); }
""",
    fragment_shader="""
#version 330
uniform sampler2D colour; uniform sampler2D height; uniform vec3 eye;
in vec3 p; in vec2 t; in vec3 pu; in vec3 pv;
out vec4 frag;
""" + shading_glsl([((0.6, -0.55, -0.58), 2.6), ((-0.8, 0.15, -0.35), 0.8)], 0.04, 87) + """
void main() {
    vec2 st = t * vec2(8.0, 4.0);
    vec2 texel = 1.0 / vec2(textureSize(height, 0));
    // dF/du = 0.004 * 8 * dh/ds, the derivative by central differences of the bilinear table.
    float hs = textureLod(height, st + vec2(texel.x, 0.0), 0.0).r - textureLod(height, st - vec2(texel.x, 0.0), 0.0).r;
    float ht = textureLod(height, st + vec2(0.0, texel.y), 0.0).r - textureLod(height, st - vec2(0.0, texel.y), 0.0).r;
    float fu = 0.004 * 8.0 * hs / (2.0 * texel.x);
    float fv = 0.004 * 4.0 * ht / (2.0 * texel.y);
    vec3 n = cross(pu, pv);
    vec3 d = (fu * cross(n, pv) - fv * cross(n, pu)) / length(n);
    vec3 nn = normalize(n + d);
    vec3 albedo = texture(colour, st).rgb;
    vec3 c = shade(nn, albedo, normalize(eye - p));
    frag = vec4(srgb(c), 1.0);
}
""",
)
vbo = ctx.buffer(vertices.tobytes())
ibo = ctx.buffer(indices.tobytes())
vao = ctx.vertex_array(prog, [(vbo, "3f 2f 3f 3f", "in_pos", "in_uv", "in_pu", "in_pv")], ibo)
texture(ctx, f"{folder}/bricks_color.png", True).use(0)
heights = texture(ctx, f"{folder}/bricks_height.png", False)
heights.filter = (moderngl.LINEAR, moderngl.LINEAR)
heights.use(1)
prog["colour"] = 0
prog["height"] = 1
prog["eye"] = (0.0, 0.0, 4.0)
prog["mvp"].write(mvp())
time_frames(ctx, vao, frames, out_png, supersample)
