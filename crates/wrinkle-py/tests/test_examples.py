"""Every script in examples/python runs as written and writes what it says."""

import os
import subprocess
import sys

import pytest

import wrinkle  # noqa: F401  (the package the examples import must be importable here)

EXAMPLES = {
    "render_default.py": ["default_scene.png"],
    "emboss_photo.py": ["embossed.png", "embossed_colour.png"],
    "make_normal_map.py": ["bricks_normal.png"],
    "compare_filters.py": ["filters.png"],
}


def test_every_example_is_listed(repo):
    assert sorted(p.name for p in (repo / "examples" / "python").glob("*.py")) == sorted(EXAMPLES)


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_example_runs(name, repo, tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, repo / "examples" / "python" / name], cwd=tmp_path, env=env,
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    for out in EXAMPLES[name]:
        assert (tmp_path / out).stat().st_size > 1000, out
