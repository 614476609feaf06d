"""isocorr.match: the same maps as the command line, Shapes reused, settings checked,
progress reported and Ctrl-C honoured."""

import json
import os
import pathlib
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import isocorr


def creature(examples, name):
    return isocorr.read_mesh(str(examples / "meshes" / name))


def true_map(examples):
    return np.loadtxt(examples / "gt" / "creature_to_moved.txt", dtype=np.int64)


def test_match_recovers_the_known_map(examples):
    m = isocorr.match(creature(examples, "creature.ply"), creature(examples, "creature_moved.ply"))
    truth = true_map(examples)
    assert m.forward.dtype == np.int32 and m.forward.shape == truth.shape
    assert np.mean(m.forward == truth) > 0.95
    assert m.reverse.shape[0] == len(creature(examples, "creature_moved.ply")[0])
    assert m.confidence.dtype == np.float32 and m.confidence.shape == m.forward.shape
    assert m.report["final"]["source_vertices"] == len(truth)
    assert 0 < m.diso < 0.05 and m.orientation > 0.9
    assert m.verdict == "ok" and m.verdict_reasons == [] and m.report["verdict"]["status"] == "ok"


def test_same_map_as_the_command_line_byte_for_byte(cli, faust_pair, tmp_path):
    source, target = faust_pair
    written = tmp_path / "map.npy"
    subprocess.run([str(cli), "match", str(source), str(target), "-o", str(written)], check=True,
                   capture_output=True)
    m = isocorr.match(isocorr.read_mesh(str(source)), isocorr.read_mesh(str(target)))
    from_cli = np.load(written)
    assert from_cli.dtype == np.int32
    assert m.forward.tobytes() == from_cli.tobytes()


def test_a_shape_reused_for_two_matches_gives_the_maps_of_fresh_ones(examples):
    V, F = creature(examples, "creature.ply")
    moved = creature(examples, "creature_moved.ply")
    shape = isocorr.Shape(V, F)
    moved_shape = isocorr.Shape(*moved)
    first = isocorr.match(shape, moved_shape)
    second = isocorr.match(moved_shape, shape)
    assert np.array_equal(first.forward, isocorr.match((V, F), moved).forward)
    assert np.array_equal(second.forward, isocorr.match(moved, (V, F)).forward)


def test_the_functional_map_carries_the_source_basis_onto_the_target_basis(examples):
    shape = isocorr.Shape(*creature(examples, "creature.ply"))
    moved = isocorr.Shape(*creature(examples, "creature_moved.ply"))
    m = isocorr.match(shape, moved)
    k = m.C.shape[0]
    assert m.C.shape == (k, k) and 0 < k <= shape.basis.shape[1]
    assert shape.basis.shape[0] == shape.num_vertices and np.all(np.diff(shape.eigenvalues) >= 0)
    pulled, aimed = shape.basis[:, :k] @ m.C, moved.basis[m.forward, :k]
    # Against a shuffled map the same basis misses by about its own size.
    shuffled = moved.basis[np.random.default_rng(0).permutation(m.forward), :k]
    assert np.linalg.norm(pulled - aimed) < 0.5 * np.linalg.norm(aimed)
    assert np.linalg.norm(shape.basis[:, :k] @ m.C - shuffled) > 0.9 * np.linalg.norm(aimed)
    assert isocorr.match(shape, moved, refine="none").C is None


def test_settings_are_checked_by_name_type_and_range(examples):
    pair = (creature(examples, "creature.ply"), creature(examples, "creature_moved.ply"))
    with pytest.raises(ValueError, match="unknown setting 'no_such_setting'"):
        isocorr.match(*pair, no_such_setting=1)
    with pytest.raises(ValueError, match="min_tracked takes an integer"):
        isocorr.match(*pair, min_tracked=2.5)
    with pytest.raises(ValueError, match="max_level0_diso"):
        isocorr.match(*pair, max_level0_diso=2.0)
    with pytest.raises(ValueError, match="refine takes one of"):
        isocorr.match(*pair, refine=3)
    shapes = [isocorr.Shape(*mesh) for mesh in pair]
    with pytest.raises(ValueError, match="preprocessing setting: give it to isocorr.Shape"):
        isocorr.match(*shapes, spectral_basis=50)
    with pytest.raises(ValueError, match="setting of the match: give it to isocorr.match"):
        isocorr.Shape(*pair[0], min_tracked=4)
    names = {row["name"]: row for row in isocorr.settings()}
    assert names["min_tracked"]["type"] == "int" and names["spectral_basis"]["scope"] == "preprocess"


def test_an_unusable_mesh_is_a_value_error(examples):
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    with pytest.raises(ValueError):
        isocorr.match((V, np.array([[0, 1, 2]])), creature(examples, "creature.ply"))


def test_progress_reaches_the_callback_in_order(examples):
    seen = []
    isocorr.match(creature(examples, "creature.ply"), creature(examples, "creature_moved.ply"),
                  progress=lambda stage, fraction: seen.append((stage, fraction)))
    assert seen and seen[-1] == ("done", 1.0)
    assert all(0 <= fraction <= 1 for _, fraction in seen)


def test_a_callback_that_raises_ends_the_match_with_its_exception(examples):
    def stop(stage, fraction):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        isocorr.match(creature(examples, "creature.ply"), creature(examples, "creature_moved.ply"), progress=stop)


def test_ctrl_c_ends_a_running_match_within_a_second(faust_pair):
    source, target = (isocorr.read_mesh(str(path)) for path in faust_pair)
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        isocorr.match(source, target)
    assert time.monotonic() - start < 1.5


def test_evaluate_scores_as_the_command_line(cli, examples, tmp_path):
    source, target = examples / "meshes" / "creature.ply", examples / "meshes" / "creature_moved.ply"
    m = isocorr.match(isocorr.read_mesh(str(source)), isocorr.read_mesh(str(target)))
    written = tmp_path / "map.npy"
    np.save(written, m.forward.astype(np.int64))  # what a user's numpy writes
    run = subprocess.run([str(cli), "eval", "meshes/creature.ply", "meshes/creature_moved.ply", str(written),
                          "--dataset", str(examples), "--json"], check=True, capture_output=True, text=True)
    from_cli = json.loads(run.stdout[run.stdout.index("{"):])
    V, F = isocorr.read_mesh(str(target))
    score = isocorr.evaluate(V, F, m.forward, true_map(examples))
    assert score["d_grd"] == from_cli["d_grd"] and score["kim_auc"] == from_cli["kim_auc"]
    assert score["evaluated"] == from_cli["evaluated"] and score["flip_free"]
    assert score["kim_curve"].shape == score["kim_thresholds"].shape
    assert isocorr.coverage(V, F, m.forward, [10, 50]) == pytest.approx(from_cli["coverage"][0:3:2])
    with pytest.raises(ValueError, match="truth has 3 entries"):
        isocorr.evaluate(V, F, m.forward, np.array([0, 1, 2]))


def test_warnings_and_notes_are_lists_of_text(examples):
    m = isocorr.match(creature(examples, "creature.ply"), creature(examples, "creature_moved.ply"))
    assert isinstance(m.warnings, list) and all(isinstance(w, str) for w in m.warnings)
    assert m.notes and all(isinstance(n, str) for n in m.notes)
    assert repr(m).startswith("<isocorr.Match: ")


def test_the_match_and_score_example_runs(examples, tmp_path):
    example = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python" / "match_and_score.py"
    out = tmp_path / "map.npy"
    run = subprocess.run([sys.executable, str(example), str(examples / "meshes" / "creature.ply"),
                          str(examples / "meshes" / "creature_moved.ply"),
                          str(examples / "gt" / "creature_to_moved.txt"), str(out)],
                         check=True, capture_output=True, text=True)
    assert "flip-free True" in run.stdout
    assert np.load(out).shape == (len(creature(examples, "creature.ply")[0]),)


def test_landmarks_are_kept_and_bad_ones_named(examples):
    source, target = creature(examples, "creature.ply"), creature(examples, "creature_moved.ply")
    truth = true_map(examples)
    landmarks = np.array([[0, truth[0]], [100, truth[100]]])
    m = isocorr.match(source, target, landmarks=landmarks)
    assert m.forward[0] == truth[0] and m.forward[100] == truth[100]
    assert m.report["landmarks"]["count"] == 2
    with pytest.raises(ValueError, match=r"landmarks\[1\]"):
        isocorr.match(source, target, landmarks=[[0, truth[0]], [0, truth[5]]])
    with pytest.raises(ValueError, match="shape"):
        isocorr.match(source, target, landmarks=[1, 2])
