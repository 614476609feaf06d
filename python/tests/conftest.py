"""Fixtures shared by the Python tests: the repository's build and the example meshes."""

import os
import pathlib
import subprocess

import pytest

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("ISOCORR_BUILD_DIR", REPOSITORY / "build"))
SHARED_DATA = pathlib.Path(os.environ.get("ISOCORR_DATA", REPOSITORY.parent / "shared" / "data"))


@pytest.fixture(scope="session")
def cli():
    """The isocorr command of the same build."""
    path = BUILD / "client" / "isocorr"
    if not path.exists():
        pytest.skip(f"no isocorr command at {path}")
    return path


@pytest.fixture(scope="session")
def examples(tmp_path_factory):
    """The bundled example pair, small: the creature and its rotated, scaled, renumbered copy."""
    folder = tmp_path_factory.mktemp("examples")
    subprocess.run([str(BUILD / "tools" / "isocorr-make-examples"), str(folder), "--subdivisions", "3"], check=True,
                   capture_output=True)
    return folder


def benchmark_pair(dataset, source, target):
    """Two meshes of ../shared/data/<dataset>/off; the test is skipped without the data."""
    folder = SHARED_DATA / dataset / "off"
    if not (folder / source).exists():
        pytest.skip(f"no benchmark data at {SHARED_DATA}")
    return folder / source, folder / target


@pytest.fixture(scope="session")
def faust_pair():
    """A real pair of FAUST meshes (5K vertices), when ../shared/data is present."""
    return benchmark_pair("faust_5k", "tr_reg_002.off", "tr_reg_007.off")


@pytest.fixture(scope="session")
def scape_mirrored_pair():
    """SCAPE 007 -> 009 (12.5K vertices, shared numbering): matched as a mirror without help."""
    return benchmark_pair("scape", "mesh007.off", "mesh009.off")
