"""A fresh install has what the README promises (issue 14, item 9): ``man kincalc-check``.

The wheel carries the man pages as data for ``<prefix>/share/man/man1`` (they were in
site-packages, where man never looks). Built here once, installed without
dependencies into a fresh virtual environment (about ten seconds), and asked of man-db
the way a user does after the Quick start: MANPATH unset, the environment's bin folder
on PATH, from which man-db derives ``<venv>/share/man``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = sorted(p.name for p in (ROOT / "man").glob("*.1"))


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    out = tmp_path_factory.mktemp("wheel")
    r = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--quiet",
                        "--wheel-dir", str(out), str(ROOT)],
                       capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        pytest.skip(f"cannot build a wheel here (no network for hatchling?): "
                    f"{r.stderr.strip().splitlines()[-1:]}")
    (whl,) = out.glob("kincalc-*.whl")
    return whl


@pytest.fixture(scope="module")
def fresh_env(wheel, tmp_path_factory):
    """A new virtual environment with the wheel installed (dependencies not needed to
    look at its files), as the Quick start makes one."""
    env = tmp_path_factory.mktemp("venv") / "env"
    venv.EnvBuilder(with_pip=False).create(env)
    r = subprocess.run([sys.executable, "-m", "pip", "--python", str(env / "bin" / "python"),
                        "install", "--no-deps", "--quiet", str(wheel)],
                       capture_output=True, text=True, timeout=600)
    if r.returncode != 0:     # pip < 22.3 has no --python: install with the venv's own pip
        venv.EnvBuilder(with_pip=True, clear=True).create(env)
        subprocess.run([str(env / "bin" / "python"), "-m", "pip", "install", "--no-deps",
                        "--quiet", str(wheel)], check=True, capture_output=True, timeout=600)
    return env


def test_wheel_puts_every_page_in_share_man_man1(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    data = sorted(n.rsplit("/", 1)[1] for n in names if "/share/man/man1/" in n
                  and n.split("/", 1)[0].endswith(".data"))
    assert data == PAGES
    assert not [n for n in names if n.startswith("kincalc/man/")], \
        "the pages are data for share/man, not package files no one reads"
    assert any(n.startswith("kincalc/robots/") for n in names), "the robot library stays"


def test_wheel_carries_the_view_page_assets(wheel):
    """kincalc view inlines its template, style and scripts from package data files:
    without them in the wheel, the command fails after install."""
    names = set(zipfile.ZipFile(wheel).namelist())
    from kincalc.analysis.view import ASSETS
    for asset in ["page.html", *ASSETS.values()]:
        assert f"kincalc/analysis/view/{asset}" in names, asset


def test_fresh_install_has_the_pages_where_man_finds_them(fresh_env):
    man1 = fresh_env / "share" / "man" / "man1"
    assert sorted(p.name for p in man1.glob("*.1")) == PAGES
    for page in PAGES:
        assert (man1 / page).read_bytes() == (ROOT / "man" / page).read_bytes()
    man = shutil.which("man")
    if man is None:
        pytest.skip("man is not installed: the pages are in place, man cannot be asked")
    env = {k: v for k, v in os.environ.items() if k not in ("MANPATH", "MANPAGER", "PAGER")}
    env["PATH"] = f"{fresh_env / 'bin'}{os.pathsep}/usr/bin{os.pathsep}/bin"
    r = subprocess.run([man, "-w", "kincalc-check"], capture_output=True, text=True, env=env,
                       timeout=60)
    assert r.returncode == 0, r.stderr
    assert Path(r.stdout.strip()) == man1 / "kincalc-check.1"
    # and without the environment on PATH, man does not find it: the test asks the
    # mechanism the README describes, not a page installed system-wide
    env["PATH"] = f"/usr/bin{os.pathsep}/bin"
    r = subprocess.run([man, "-w", "kincalc-check"], capture_output=True, text=True, env=env,
                       timeout=60)
    assert str(fresh_env) not in r.stdout
