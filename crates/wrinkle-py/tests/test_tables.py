"""Scenes built from Python objects: the same scene as the file that says the same."""

import numpy as np
import pytest

import wrinkle
from test_scene import SPHERE


def test_a_built_scene_renders_like_its_file():
    scene = wrinkle.Scene.build(
        camera=wrinkle.Camera(eye=(0.0, 0.0, 4.0), look_at=np.zeros(3), fov_y=40.0, background=[0.0, 0.0, 0.0]),
        lights=[wrinkle.Light(type="directional", direction=[0.0, 0.0, -1.0])],
        objects=[wrinkle.Sphere(radius=1.0, material=wrinkle.Material(color=[0.8, 0.8, 0.8], specular=0.0))],
    )
    assert np.array_equal(scene.render(40, 30)["color"], wrinkle.Scene.from_toml(SPHERE).render(40, 30)["color"])


def test_bumps_and_generators_from_objects_change_the_picture():
    def sphere(bump):
        material = wrinkle.Material(color=[0.8, 0.8, 0.8], bump=bump) if bump else wrinkle.Material(color=[0.8, 0.8, 0.8])
        return wrinkle.Scene.build(
            camera=wrinkle.Camera(eye=[0, 0, 4], look_at=[0, 0, 0], fov_y=40),
            lights=[wrinkle.Light(type="directional", direction=[0.5, -0.5, -1])],
            objects=[wrinkle.Sphere(radius=1, material=material)],
        ).render(64, 64)["color"]

    bumped = sphere(wrinkle.Bump(generator={"kind": "bricks", "size": 128}, scale=0.02))
    assert np.abs(bumped - sphere(None)).mean() > 0.005


def test_errors_name_the_field_of_the_object():
    with pytest.raises(wrinkle.SceneError, match=r"objects\[0\].material.bump.generator.rows"):
        wrinkle.Scene.build(
            camera=wrinkle.Camera(eye=[0, 0, 4], look_at=[0, 0, 0]),
            objects=[wrinkle.Sphere(material=wrinkle.Material(bump=wrinkle.Bump(generator={"kind": "bricks", "rows": 3})))],
        )
    with pytest.raises(wrinkle.SceneError, match=r"objects\[0\].radius"):
        wrinkle.Scene.build(camera=wrinkle.Camera(eye=[0, 0, 4], look_at=[0, 0, 0]), objects=[wrinkle.Sphere(radius=-1)])


def test_tables_print_and_compare():
    assert repr(wrinkle.Sphere(radius=2)) == "Sphere(radius=2)"
    assert wrinkle.Sphere(radius=2) == wrinkle.Sphere(radius=2) != wrinkle.Box(radius=2)
    assert wrinkle.Sphere(radius=2).to_dict() == {"shape": "sphere", "radius": 2}
