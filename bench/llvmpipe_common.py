"""What the llvmpipe peers share: the UV sphere of wrinkle's `sphere` shape as triangles, an EGL context on
Mesa's llvmpipe (moderngl), mipmapped textures, the camera at (0, 0, 4) with fov_y 40, timed frames and the
frame written as a PNG. Needs: pip install moderngl numpy pillow."""
import statistics
import time

import moderngl
import numpy as np
from PIL import Image

W, H = 1920, 1080



# sRGB's encoding, for fragment shaders that compute in linear light.
SRGB_GLSL = """
vec3 srgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
"""


def shading_glsl(lights, specular, shininess):
    """GLSL of wrinkle's Blinn-Phong under directional lights (docs/scene-format.md, "Shading"): `vec3 shade(vec3 n,
    vec3 albedo, vec3 v)` in linear light, for `lights` given as the scene gives them ((direction the light
    travels, intensity) pairs), and SRGB_GLSL."""
    to_light = ", ".join("-normalize(vec3({}, {}, {}))".format(*d) for d, _ in lights)
    k = ", ".join(str(float(e)) for _, e in lights)
    return f"""
vec3 shade(vec3 n, vec3 albedo, vec3 v) {{
    vec3 dirs[{len(lights)}] = vec3[{len(lights)}]({to_light});
    float k[{len(lights)}] = float[{len(lights)}]({k});
    vec3 c = vec3(0.0);
    for (int i = 0; i < {len(lights)}; i++) {{
        float ndl = dot(n, dirs[i]);
        if (ndl > 0.0) {{
            float ndh = max(dot(n, normalize(dirs[i] + v)), 0.0);
            c += k[i] * (albedo * ndl + vec3({float(specular)} * pow(ndh, {float(shininess)})));
        }}
    }}
    return c;
}}
""" + SRGB_GLSL


def uv_sphere(nu, nv):
    """Vertices (position, normal, uv, dP/du, dP/dv) and triangle indices of the unit sphere with the `sphere`
    shape's (u, v): u the longitude from +x (0.25 at -z), v the latitude from the south pole."""
    u, v = np.arange(nu + 1) / nu, np.arange(nv + 1) / nv
    phi, theta = np.meshgrid(2 * np.pi * u, np.pi * (v - 0.5))
    c, s = np.cos(theta), np.sin(theta)
    pos = np.stack([c * np.cos(phi), s, -c * np.sin(phi)], -1).reshape(-1, 3)
    uv = np.stack(np.meshgrid(u, v), -1).reshape(-1, 2)
    pu = 2 * np.pi * np.stack([-c * np.sin(phi), np.zeros_like(phi), -c * np.cos(phi)], -1).reshape(-1, 3)
    pv = np.pi * np.stack([-s * np.cos(phi), c, s * np.sin(phi)], -1).reshape(-1, 3)
    a = (np.arange(nv)[:, None] * (nu + 1) + np.arange(nu)[None, :]).reshape(-1)
    b, cc, d = a + 1, a + nu + 2, a + nu + 1
    indices = np.stack([a, b, cc, a, cc, d], 1).astype("i4").reshape(-1)
    return pos, uv, pu, pv, indices


def context():
    ctx = moderngl.create_standalone_context(backend="egl")
    return ctx, ctx.info["GL_RENDERER"]


def texture(ctx, path, srgb):
    """A trilinear, repeating texture (sRGB-decoded when `srgb`), rows bottom-up as OpenGL reads them."""
    img = Image.open(path).convert("RGBA").transpose(Image.FLIP_TOP_BOTTOM)
    tex = ctx.texture(img.size, 4, img.tobytes(), internal_format=0x8C43 if srgb else None)
    tex.build_mipmaps()
    tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    return tex


def view_projection(eye=(0.0, 0.0, 4.0)):
    """Projection times view (4x4, row-major) of the benchmark camera: `eye` looking at the origin, +Y up,
    fov_y 40, 1920x1080."""
    f = 1.0 / np.tan(np.radians(40.0) / 2)
    near, far = 0.1, 100.0
    proj = np.array([[f * H / W, 0, 0, 0], [0, f, 0, 0],
                     [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]])
    eye = np.array(eye, float)
    back = eye / np.linalg.norm(eye)
    right = np.cross([0.0, 1.0, 0.0], back)
    right /= np.linalg.norm(right)
    up = np.cross(back, right)
    view = np.eye(4)
    view[:3, :3] = [right, up, back]
    view[:3, 3] = -view[:3, :3] @ eye
    return proj @ view


def mvp(eye=(0.0, 0.0, 4.0)):
    """`view_projection` as the bytes of a GLSL mat4 uniform (column-major)."""
    return view_projection(eye).T.astype("f4").tobytes()


def time_frames(ctx, vao, frames, out_png=None, supersample=1):
    """Renders frames + 1 frames into a 1920x1080 framebuffer, or one `supersample` times as wide and high
    (supersampling: supersample^2 samples per pixel), with depth test and back faces culled, each ended by
    glFinish; prints the median and best of all but the first; writes the last as out_png when given (box
    filtered down to 1920x1080)."""
    fbo = ctx.simple_framebuffer((W * supersample, H * supersample), components=4)
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
    if out_png:
        frame = Image.frombytes("RGBA", fbo.size, fbo.read(components=4)).transpose(Image.FLIP_TOP_BOTTOM)
        frame.convert("RGB").resize((W, H), Image.BOX).save(out_png)
    print(f"llvmpipe median_ms={statistics.median(times):.2f} min_ms={min(times):.2f} frames={frames} "
          f"renderer={ctx.info['GL_RENDERER']!r}")
