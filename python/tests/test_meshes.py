"""read_mesh and write_mesh: numpy arrays in and out, and clear errors."""

import numpy as np
import pytest

import isocorr


def test_read_mesh_gives_float_vertices_and_int_triangles(examples):
    V, F = isocorr.read_mesh(str(examples / "meshes" / "creature.ply"))
    assert V.dtype == np.float64 and V.ndim == 2 and V.shape[1] == 3
    assert F.dtype == np.int32 and F.ndim == 2 and F.shape[1] == 3
    assert F.min() == 0 and F.max() == len(V) - 1


@pytest.mark.parametrize("extension", [".off", ".obj"])
def test_text_formats_round_trip_exactly(tmp_path, extension):
    V = np.array([[0.1, 1 / 3, -2.25], [1e-300, 0, 7], [0, -2.25e17, 0], [0.7, 0.2, 1e3]])
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    path = str(tmp_path / ("tetra" + extension))
    isocorr.write_mesh(path, V, F)
    V2, F2 = isocorr.read_mesh(path)
    assert np.array_equal(V2, V)
    assert np.array_equal(F2, F)


def test_bad_arrays_are_refused_naming_the_problem(tmp_path):
    V = np.zeros((4, 3))
    F = np.array([[0, 1, 2]])
    with pytest.raises(ValueError, match=r"V must be an array of shape \(n, 3\), got shape \(4, 2\)"):
        isocorr.write_mesh(str(tmp_path / "a.off"), np.zeros((4, 2)), F)
    with pytest.raises(ValueError, match="F: face 0 names vertex 9, outside V's 4 vertices"):
        isocorr.write_mesh(str(tmp_path / "a.off"), V, np.array([[0, 1, 9]]))
    with pytest.raises(ValueError, match="not finite"):
        isocorr.write_mesh(str(tmp_path / "a.off"), np.array([[0, 0, np.nan]] * 4), F)
    with pytest.raises(ValueError, match=r"must end in \.off, \.obj or \.ply"):
        isocorr.write_mesh(str(tmp_path / "a.stl"), V, F)


def test_malformed_file_is_a_value_error_naming_the_file(tmp_path):
    path = tmp_path / "broken.off"
    path.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    with pytest.raises(ValueError, match="broken.off"):
        isocorr.read_mesh(str(path))
