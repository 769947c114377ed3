"""Scenes from Python objects: each class is one table of the scene file (docs/scene-format.md) with its
fields as keyword arguments, so that a scene is written as code and checked by the same parser as a file
(an error names the field's path, `objects[0].material.bump.scale`).

    scene = wrinkle.Scene.build(
        camera=wrinkle.Camera(eye=[0, 0, 4], look_at=[0, 0, 0], fov_y=40),
        lights=[wrinkle.Light(type="directional", direction=[0.5, -0.5, -1])],
        objects=[wrinkle.Sphere(radius=1, material=wrinkle.Material(color=[0.8, 0.3, 0.2],
                                bump=wrinkle.Bump(generator={"kind": "bricks"}, scale=0.01)))],
    )
"""

from __future__ import annotations

from typing import Any, Dict


class Table:
    """One table of a scene: its fields by the scene file's names. Nested tables may be `Table`s or
    dictionaries; lists hold numbers, strings or tables."""

    #: A field every table of this class holds (a shape's "shape"), set by the subclass.
    _implied: Dict[str, Any] = {}

    def __init__(self, **fields: Any) -> None:
        self.fields = {**self._implied, **fields}

    def to_dict(self) -> Dict[str, Any]:
        """The table as the dictionary `Scene.from_dict` reads."""
        return {k: plain(v) for k, v in self.fields.items()}

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and other.fields == self.fields

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.fields.items() if k not in self._implied)
        return f"{type(self).__name__}({args})"


def plain(value: Any) -> Any:
    """Tables as dictionaries, tuples and arrays as lists, all the way down."""
    if isinstance(value, Table):
        return value.to_dict()
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if hasattr(value, "tolist"):  # NumPy arrays and scalars
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return value


def _table(name: str, doc: str, **implied: Any) -> type:
    return type(name, (Table,), {"__doc__": doc, "_implied": implied, "__module__": __name__})


Camera = _table("Camera", "[camera]: eye, look_at, up, fov_y, projection, height, background.")
Light = _table(
    "Light",
    "[[light]]: type (directional, point, spot, ambient, environment), direction, position, color, intensity, "
    "angle, falloff, up, texture, shadow, shadow_size, shadow_bias.",
)
Material = _table(
    "Material",
    "[object.material]: color, specular, shininess, texture, bump, layer, alpha_mode, opacity, reflect, ... "
    "(docs/scene-format.md).",
)
Bump = _table(
    "Bump",
    "[object.material.bump]: one source (map, generator, procedural, offsets), scale, filter, mapping, invariant, "
    "formula, parallax, displacement.",
)
Environment = _table("Environment", "[environment]: map, layout, background, and the filter options.")
Volume = _table("Volume", "[[volume]]: a hypertextured ellipsoid: center, radius or radii, density, step, ...")
Sphere = _table("Sphere", "A sphere: radius, and every object field (transform, material, mapping, ...).", shape="sphere")
Cylinder = _table("Cylinder", "A cylinder: radius, height, and every object field.", shape="cylinder")
Torus = _table("Torus", "A torus: major_radius, minor_radius, and every object field.", shape="torus")
Patch = _table("Patch", "A bilinear patch: corners, uv_corners, and every object field.", shape="patch")
Bicubic = _table("Bicubic", "A bicubic Bezier patch: points (16), and every object field.", shape="bicubic")
Box = _table("Box", "A box: size, and every object field.", shape="box")
Billboard = _table("Billboard", "A billboard: width, height, align, axis, and every object field.", shape="billboard")
Mesh = _table("Mesh", "A model file: file (OBJ, glTF, GLB), two_sided, and every object field.", shape="mesh")
