#!/usr/bin/env python3
"""The peer of bench/shadows/scene.toml: a floor and two spheres (256 x 128 quad UV meshes) under a sun with a
shadow map (an orthographic 1024x1024 depth texture fitted to the scene's bounding box seen along the light,
rendered every frame) and an ambient light; the lookup is OpenGL's 2x2 percentage-closer compare, the receiver
moved off its surface along its normal by a texel and its depth biased by a slope-scaled half texel; shadows
darken the sun's diffuse and specular terms, as wrinkle's. Rendered by Mesa's llvmpipe at 1920x1080, 1 spp.
Prints the median frame time (both passes) and writes the last frame.

Usage: llvmpipe_shadows.py OUT.png [FRAMES]   (needs: pip install moderngl numpy pillow)
"""
import sys

import moderngl
import numpy as np

from llvmpipe_common import SRGB_GLSL, context, mvp, time_frames, uv_sphere

out_png = sys.argv[1]
frames = int(sys.argv[2]) if len(sys.argv) > 2 else 9
eye = (0.0, 3.2, 8.0)
sun = np.array([0.5, -0.8, -0.35]) / np.linalg.norm([0.5, -0.8, -0.35])
MAP = 1024

# The objects: vertices (position, normal) in the world, with their materials (albedo, specular, shininess).
# 256 x 128 quads: the larger sphere is about 200 pixels tall, so its outline stays smooth.
pos, _, _, _, sphere_indices = uv_sphere(256, 128)
floor = np.array([[-6, 0, 4], [6, 0, 4], [6, 0, -6], [-6, 0, -6]], float)
objects = [
    (np.concatenate([floor, np.tile([0.0, 1.0, 0.0], (4, 1))], 1), np.array([0, 1, 2, 0, 2, 3], "i4"),
     (0.8, 0.8, 0.75), 0.0, 1.0),
    (np.concatenate([0.8 * pos + [-1.2, 0.8, 0.0], pos], 1), sphere_indices, (0.7, 0.2, 0.15), 0.4, 40.0),
    (np.concatenate([0.5 * pos + [1.0, 0.5, 0.5], pos], 1), sphere_indices, (0.2, 0.4, 0.7), 0.4, 40.0),
]

# The sun's orthographic view of the scene's bounding box: x, y across the light, z along it.
back = -sun
right = np.cross([0.0, 1.0, 0.0], back)
right /= np.linalg.norm(right)
up = np.cross(back, right)
corners = np.array([[x, y, z] for x in (-6, 6) for y in (0, 1.6) for z in (-6, 4)], float)
local = corners @ np.array([right, up, back]).T
lo, hi = local.min(0), local.max(0)
light_view = np.eye(4)
light_view[:3, :3] = [right, up, back]
scale = np.diag([2 / (hi[0] - lo[0]), 2 / (hi[1] - lo[1]), -2 / (hi[2] - lo[2]), 1.0])
scale[:3, 3] = [-(hi[0] + lo[0]) / (hi[0] - lo[0]), -(hi[1] + lo[1]) / (hi[1] - lo[1]), (hi[2] + lo[2]) / (hi[2] - lo[2])]
light_vp = scale @ light_view
texel = max(hi[0] - lo[0], hi[1] - lo[1]) / MAP

ctx, _ = context()
depth_only = ctx.program(
    vertex_shader="""
#version 330
uniform mat4 light_vp;
in vec3 in_pos;
void main() { gl_Position = light_vp * vec4(in_pos, 1.0); }
""",
    fragment_shader="#version 330\nvoid main() {}\n",
)
lit = ctx.program(
    vertex_shader="""
#version 330
uniform mat4 mvp;
in vec3 in_pos; in vec3 in_normal;
out vec3 p; out vec3 n;
void main() { p = in_pos; n = in_normal; gl_Position = mvp * vec4(in_pos, 1.0); }
""",
    fragment_shader="""
#version 330
uniform mat4 light_vp; uniform sampler2DShadow shadow; uniform vec3 eye; uniform vec3 to_sun; uniform float texel;
uniform vec3 albedo; uniform float ks; uniform float shininess;
in vec3 p; in vec3 n;
out vec4 frag;
""" + SRGB_GLSL + """
void main() {
    vec3 N = normalize(n);
    vec3 V = normalize(eye - p);
    if (dot(N, V) < 0.0) N = -N;  // the floor is lit from both sides
    float ndl = dot(N, to_sun);
    vec3 c = 0.1 * albedo;
    if (ndl > 0.0) {
        float sine = sqrt(max(1.0 - ndl * ndl, 0.0));
        vec4 q = light_vp * vec4(p + N * texel * sine, 1.0);
        vec3 s = q.xyz / q.w * 0.5 + 0.5;
        float bias = 0.5 * texel * (1.0 + sine / max(ndl, 0.05)) / 20.0;
        float seen = texture(shadow, vec3(s.xy, s.z - bias));
        float ndh = max(dot(N, normalize(to_sun + V)), 0.0);
        c += seen * 0.9 * (albedo * ndl + vec3(ks * pow(ndh, shininess)));
    }
    frag = vec4(srgb(c), 1.0);
}
""",
)
draws = []
for vertices, indices, albedo, ks, shininess in objects:
    vbo, ibo = ctx.buffer(vertices.astype("f4").tobytes()), ctx.buffer(indices.astype("i4").tobytes())
    draws.append((ctx.vertex_array(depth_only, [(vbo, "3f 12x", "in_pos")], ibo),
                  ctx.vertex_array(lit, [(vbo, "3f 3f", "in_pos", "in_normal")], ibo), albedo, ks, shininess))
depth = ctx.depth_texture((MAP, MAP))
depth.compare_func = "<="
depth.filter = (moderngl.LINEAR, moderngl.LINEAR)
shadow_fbo = ctx.framebuffer(depth_attachment=depth)
light_bytes = light_vp.T.astype("f4").tobytes()
depth_only["light_vp"].write(light_bytes)
lit["light_vp"].write(light_bytes)
lit["mvp"].write(mvp(eye))
lit["eye"] = eye
lit["to_sun"] = tuple(-sun)
lit["texel"] = texel
lit["shadow"] = 0


class Scene:
    """The shadow pass into the depth texture, then the frame (time_frames' framebuffer)."""

    def render(self):
        frame = ctx.fbo
        shadow_fbo.use()
        shadow_fbo.clear(depth=1.0)
        ctx.disable(moderngl.CULL_FACE)
        for shadow_vao, *_ in draws:
            shadow_vao.render()
        frame.use()
        depth.use(0)
        for _, vao, albedo, ks, shininess in draws:
            lit["albedo"], lit["ks"], lit["shininess"] = albedo, ks, shininess
            vao.render()


time_frames(ctx, Scene(), frames, out_png)
