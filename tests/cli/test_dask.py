"""The Dask recipe of README's *Scaling out with Dask* (examples/dask_batch.py), run on a
local cluster of two worker processes, and the pickling of robots it relies on.

The recipe is imported from the example file itself, so the documented code is what
runs. dask is in the ``test`` extra: when it is missing these tests fail (they are
never skipped).
"""

import importlib.util
import json
import pickle
import sys
from pathlib import Path

import numpy as np
import pytest

import kincalc
from kincalc.ik.selftest import sample_configurations
from kincalc.conventions.library import bundled_names, library_dir

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "dask_batch.py"


def _generating_found(robot, Q, q, valid, tol=1e-6):
    """(N,) bool: Q[i] is among the valid solutions q[i] (revolute joints modulo 2 pi)."""
    d = q - Q[:, None, :]
    d = np.where(robot.is_revolute, np.angle(np.exp(1j * d)), d)
    return (valid & np.all(np.abs(d) < tol, axis=-1)).any(axis=-1)


def _my_arm(tmp_path):
    """A user's robot file outside the library: the PUMA 560 renamed, with a longer upper arm."""
    text = (library_dir() / "puma560.yaml").read_text()
    assert "name: puma560\n" in text and "a2: 0.4318 " in text
    path = tmp_path / "my_arm.yaml"
    path.write_text(text.replace("name: puma560\n", "name: my_arm\n").replace("a2: 0.4318 ", "a2: 0.5 "))
    return path


# --- pickling: what carries a robot to the workers -------------------------------

@pytest.mark.parametrize("name", bundled_names())
def test_bundled_robot_pickles(name):
    robot = kincalc.load_robot(name)
    Q = sample_configurations(robot, 50, np.random.default_rng(0))
    fresh = pickle.loads(pickle.dumps(robot))           # before any cached chain exists
    T = robot.fk(Q)
    used = pickle.loads(pickle.dumps(robot))            # with the cached chain
    for copy in (fresh, used):
        assert copy == robot and hash(copy) == hash(robot)
        assert (copy.name, copy.path, copy.title) == (robot.name, robot.path, robot.title)
        assert np.array_equal(copy.home, robot.home)
        assert np.array_equal(copy.limits, robot.limits)
        assert np.array_equal(copy.fk(Q), T)
        assert np.array_equal(copy.jacobian(Q), robot.jacobian(Q))


def test_robot_from_a_deleted_file_unpickles_and_solves(tmp_path):
    path = _my_arm(tmp_path)
    robot = kincalc.load_robot(str(path))
    assert robot.name == "my_arm"
    data = pickle.dumps(robot)
    path.unlink()                                        # the copy must not need the file
    copy = pickle.loads(data)
    assert copy == robot and hash(copy) == hash(robot)
    Q = sample_configurations(robot, 500, np.random.default_rng(1))
    T = robot.fk(Q)
    assert not np.allclose(T, kincalc.load_robot("puma560").fk(Q))   # really another arm
    assert np.array_equal(copy.fk(Q), T)
    a, b = robot.ik_batch(T), copy.ik_batch(T)
    assert np.array_equal(a.q, b.q, equal_nan=True) and np.array_equal(a.valid, b.valid)


# --- the recipe on a local cluster ---------------------------------------------------

@pytest.fixture(scope="module")
def recipe():
    try:
        for name in ("dask.array", "dask.distributed"):
            importlib.import_module(name)
    except ImportError as e:
        pytest.fail(f"dask is not installed ({e}): it is in the test extra, "
                    "install with pip install '.[test]'", pytrace=False)
    spec = importlib.util.spec_from_file_location("dask_batch", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def client():
    from dask.distributed import Client, LocalCluster
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    with cluster, Client(cluster) as client:
        yield client


def _solve_on_cluster(recipe, robot, T, chunk):
    import dask
    import dask.array as da
    q, valid = recipe.solve_poses(robot, da.from_array(T, chunks=(chunk, 4, 4)))
    return dask.compute(q, valid)


def _workers_ran_ik(client):
    return any(client.run(lambda: "kincalc.ik.engine" in sys.modules).values())


@pytest.mark.parametrize("name", ["ur5", "puma560"])
def test_recipe_gives_the_local_solutions(recipe, client, name):
    robot = kincalc.load_robot(name)
    Q = sample_configurations(robot, 20_000, np.random.default_rng(2))
    T = robot.fk(Q)
    q, valid = _solve_on_cluster(recipe, robot, T, chunk=6_000)    # 3 chunks of 6000, one of 2000
    local = robot.ik_batch(T)
    assert q.shape == local.q.shape and valid.shape == local.valid.shape == (20_000, q.shape[1])
    assert np.array_equal(q, local.q, equal_nan=True)
    assert np.array_equal(valid, local.valid)
    found = _generating_found(robot, Q, q, valid)
    assert found.all(), f"{np.sum(~found)} of {len(Q)} generating configurations not among the solutions"
    assert _workers_ran_ik(client)


def test_recipe_with_a_user_file_absent_from_the_workers(recipe, client, tmp_path):
    path = _my_arm(tmp_path)
    robot = kincalc.load_robot(str(path))
    path.unlink()                                        # the robot travels pickled, not as a file
    Q = sample_configurations(robot, 5_000, np.random.default_rng(3))
    T = robot.fk(Q)
    q, valid = _solve_on_cluster(recipe, robot, T, chunk=2_000)
    local = robot.ik_batch(T)
    assert np.array_equal(q, local.q, equal_nan=True) and np.array_equal(valid, local.valid)
    assert _generating_found(robot, Q, q, valid).all()


def test_workers_keep_freed_memory_despite_the_nannys_trim_threshold(recipe, client):
    # the nanny's MALLOC_TRIM_THRESHOLD_=65536 made ik_batch map its temporaries afresh
    # (a quarter to half speed); ik_batch sets glibc's thresholds itself (kincalc.memory)
    import platform
    from kincalc import memory
    robot = kincalc.load_robot("ur5")
    _solve_on_cluster(recipe, robot, robot.fk(np.zeros((4, 6))), chunk=2)
    glibc = sys.platform.startswith("linux") and platform.libc_ver()[0] == "glibc"
    assert set(client.run(lambda: memory._kept).values()) == {glibc}


def test_run_job_summary_matches_a_local_run(recipe, client):
    robot = kincalc.load_robot("ur5")
    poses, chunk, seed = 10_000, 3_000, 7
    summary = recipe.run_job(robot, poses, chunk, seed)
    # the same job without dask: the example's own per-chunk sampler, then ik_batch
    Q = np.concatenate([recipe._sample_block(np.arange(i, min(i + chunk, poses)), robot, seed)
                        for i in range(0, poses, chunk)])
    local = robot.ik_batch(robot.fk(Q))
    hist = np.bincount(local.counts, minlength=9)
    assert summary["poses"] == poses and summary["chunks"] == 4
    assert summary["solution_slots"] == local.q.shape[1]
    assert summary["family"] == local.family
    assert summary["solutions_per_pose"] == {str(k): int(c) for k, c in enumerate(hist) if c}
    assert summary["round_trip_found"] == _generating_found(robot, Q, local.q, local.valid).mean() == 1.0
    assert summary["poses_per_second"] > 0


def test_main_on_a_running_scheduler(recipe, client, tmp_path, capsys):
    path = _my_arm(tmp_path)
    status = recipe.main(["--scheduler", client.scheduler.address, "--robot", str(path),
                          "--poses", "4000", "--chunk", "1500"])
    out = json.loads(capsys.readouterr().out)
    assert status == 0
    assert out["robot"] == "my_arm" and out["workers"] == 2 and out["threads"] == 2
    assert out["scheduler"] == client.scheduler.address
    assert out["chunks"] == 3 and sum(out["solutions_per_pose"].values()) == 4000
    assert out["round_trip_found"] == 1.0


def test_main_refuses_a_robot_ik_batch_cannot_solve(recipe, capsys):
    assert recipe.main(["--robot", "iiwa7", "--poses", "10"]) == 2      # before any cluster starts
    assert "iiwa7" in capsys.readouterr().err


def test_solve_poses_wants_chunks_along_the_pose_axis_only(recipe):
    import dask.array as da
    robot = kincalc.load_robot("ur5")
    T = da.from_array(np.tile(np.eye(4), (10, 1, 1)), chunks=(5, 2, 4))
    with pytest.raises(ValueError, match="pose axis only"):
        recipe.solve_poses(robot, T)
