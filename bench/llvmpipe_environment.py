#!/usr/bin/env python3
"""The peer of bench/environment/scene.toml: a chrome sphere (a 512 x 256 quad UV mesh) mirroring the latlong HDR
environment scenes/maps/sky.hdr (turned 20 degrees about +Y), which is also the background; the reflection R =
2 (N.V) N - V weighted by Schlick's F = reflect + (1 - reflect)(1 - N.V)^5, Blinn-Phong under one directional
light; the environment read trilinearly (RGB float, mipmapped) with the derivatives of its (s, t) taken across
the seam. Rendered by Mesa's llvmpipe at 1920x1080, 1 spp: a full-screen triangle for the background, then the
sphere. Prints the median frame time and writes the last frame.

Usage: llvmpipe_environment.py OUT.png [FRAMES]   (from the repository root's bench/; needs: pip install
moderngl numpy pillow opencv-python-headless)
"""
import sys

import cv2
import moderngl
import numpy as np

from llvmpipe_common import SRGB_GLSL, context, mvp, shading_glsl, time_frames, uv_sphere, view_projection

out_png = sys.argv[1]
frames = int(sys.argv[2]) if len(sys.argv) > 2 else 9
eye = (0.0, 0.3, 4.0)

# The map's frame: directions are turned by -20 degrees about +Y before the lookup (the scene's rotate = 20).
ENV_GLSL = """
uniform sampler2D env;
const float PI = 3.14159265358979;
vec2 latlong(vec3 d) {
    float a = radians(-20.0);
    d = vec3(cos(a) * d.x + sin(a) * d.z, d.y, -sin(a) * d.x + cos(a) * d.z);
    return vec2(0.5 + atan(d.x, -d.z) / (2.0 * PI), 0.5 + asin(clamp(d.y, -1.0, 1.0)) / PI);
}
vec3 environment(vec3 d) {
    vec2 st = latlong(normalize(d));
    // The derivatives across the seam (s jumps by 1 there) as the neighbour's s would be without the wrap.
    vec2 dx = dFdx(st), dy = dFdy(st);
    dx.x -= round(dx.x);
    dy.x -= round(dy.x);
    return textureGrad(env, st, dx, dy).rgb;
}
"""

ctx, _ = context()
background = ctx.program(
    vertex_shader="""
#version 330
in vec2 in_xy;
out vec2 ndc;
void main() { ndc = in_xy; gl_Position = vec4(in_xy, 1.0, 1.0); }
""",
    fragment_shader="""
#version 330
uniform mat4 inverse_vp; uniform vec3 eye;
in vec2 ndc;
out vec4 frag;
""" + ENV_GLSL + SRGB_GLSL + """
void main() {
    vec4 far = inverse_vp * vec4(ndc, 1.0, 1.0);
    frag = vec4(srgb(environment(far.xyz / far.w - eye)), 1.0);
}
""",
)
sphere = ctx.program(
    vertex_shader="""
#version 330
uniform mat4 mvp;
in vec3 in_pos;
out vec3 p;
void main() { p = in_pos; gl_Position = mvp * vec4(in_pos, 1.0); }
""",
    fragment_shader="""
#version 330
uniform vec3 eye;
in vec3 p;
out vec4 frag;
""" + ENV_GLSL + shading_glsl([((-0.45, -0.55, 0.7), 1.0)], 0.5, 200) + """
void main() {
    vec3 n = normalize(p);
    vec3 v = normalize(eye - p);
    float ndv = max(dot(n, v), 0.0);
    vec3 f0 = vec3(0.9, 0.9, 0.92);
    vec3 fresnel = f0 + (1.0 - f0) * pow(1.0 - ndv, 5.0);
    vec3 c = shade(n, vec3(0.02), v) + fresnel * environment(2.0 * dot(n, v) * n - v);
    frag = vec4(srgb(c), 1.0);
}
""",
)
pos, _, _, _, indices = uv_sphere(512, 256)
sphere_vao = ctx.vertex_array(sphere, [(ctx.buffer(pos.astype("f4").tobytes()), "3f", "in_pos")],
                              ctx.buffer(indices.tobytes()))
quad = ctx.vertex_array(background, [(ctx.buffer(np.array([-1, -1, 3, -1, -1, 3], "f4").tobytes()), "2f", "in_xy")])

# The HDR map as OpenCV reads it (BGR, top row first), flipped to OpenGL's rows and RGB.
hdr = cv2.imread("../scenes/maps/sky.hdr", cv2.IMREAD_ANYDEPTH | cv2.IMREAD_COLOR)[::-1, :, ::-1].astype("f4")
env = ctx.texture((hdr.shape[1], hdr.shape[0]), 3, np.ascontiguousarray(hdr).tobytes(), dtype="f4")
env.build_mipmaps()
env.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
env.repeat_y = False
env.use(0)
for prog in (background, sphere):
    prog["env"] = 0
    prog["eye"] = eye
sphere["mvp"].write(mvp(eye))
background["inverse_vp"].write(np.linalg.inv(view_projection(eye)).T.astype("f4").tobytes())


class Scene:
    """Both draws, as one `render` for time_frames: the background first, without depth, then the sphere."""

    def render(self):
        ctx.disable(moderngl.DEPTH_TEST)
        quad.render()
        ctx.enable(moderngl.DEPTH_TEST)
        sphere_vao.render()


time_frames(ctx, Scene(), frames, out_png)
