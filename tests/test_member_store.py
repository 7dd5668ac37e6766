"""The tasks of a scene of independent tasks stored by their content (``validation.runner.member_key``,
``validation.members.load_member``): the same point in another scene (a rig's, named otherwise, its inputs
equal within rounding) is read back, not run again; a point whose physics changed, or a task that
failed, runs again. Truth: the count of the runs a store makes (``run_member`` counted)."""
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace

import pytest

from validation import compare, runner
from validation.catalogue import CATALOGUE


@pytest.fixture
def counted(monkeypatch):
    """``run_member`` replaced by a counter returning a point's row data (no solve)."""
    calls = []

    def fake(s, task):
        sv = s.typed_variants[task["variant"]].scene(s)
        calls.append((s.name, sv.b, sv.kx, sv.mu))
        return {"variant": task["variant"], "b": sv.b, "kx": sv.kx, "runtime_s": 1.0,
                **({"failed": "no convergence"} if sv.kx == 3e6 else {})}

    monkeypatch.setattr(runner, "run_member", fake)
    return calls


def _scenes():
    s = CATALOGUE["halfspace-points"]
    v = [dict(x) for x in s.variants[:3]]
    a = replace(s, variants=tuple(v[:2]))
    # the same second point under another name, its k_x off by rounding (a file's number against the code's)
    w = {**v[1], "kx": v[1]["kx"] * (1 + 1e-14)}
    b = replace(s, name="my-points", title="mine", notes="", variants=(w, v[2]))
    return a, b


@pytest.mark.parametrize("executor", [None, "threads"])
def test_a_point_stored_by_another_scene_is_read_back(tmp_path, counted, executor):
    a, b = _scenes()
    ex = ThreadPoolExecutor(2) if executor else None
    try:
        assert compare.run_all([a], tmp_path, executor=ex, log=lambda m: None) == {a.name: "ok"}
        assert len(counted) == 2
        said = []
        assert compare.run_all([b], tmp_path, executor=ex, log=said.append) == {b.name: "ok"}
        assert any("1 of 2 task(s) stored by content: read back" in m for m in said), said
        assert len(counted) == 3 and counted[-1][1:3] == (b.typed_variants[1].scene(b).b, b.typed_variants[1].kx)
        from validation.store import load_scene

        res = load_scene(tmp_path, b.name)
        rows = res["points"]
        assert [r["variant"] for r in rows] == [0, 1]  # the stored point at its index in the reading scene
        assert rows[0]["kx"] == b.typed_variants[0].kx  # this scene's point, not the one the store ran
        assert res["members_cpu_s"] == 1.0  # the point read back cost nothing
        # every task stored: the scene is reduced without running one
        c = replace(b, name="again")
        assert compare.run_all([c], tmp_path, executor=ex, log=lambda m: None) == {c.name: "ok"}
        assert len(counted) == 3
        # --force reruns every point
        compare.run_all([c], tmp_path, executor=ex, force=True, log=lambda m: None)
        assert len(counted) == 5
        # another friction: new physics, run again
        d = replace(b, name="other-mu", mu=b.mu * 1.5)
        compare.run_all([d], tmp_path, executor=ex, log=lambda m: None)
        assert len(counted) == 7
    finally:
        if ex:
            ex.shutdown()


def test_a_failed_task_is_not_stored(tmp_path, counted):
    a, _ = _scenes()
    bad = replace(a, variants=({**a.variants[0], "kx": 3e6},))
    compare.run_all([bad], tmp_path, log=lambda m: None)
    compare.run_all([replace(bad, name="again")], tmp_path, log=lambda m: None)
    assert len(counted) == 2
    assert not (tmp_path / "members").exists() or not any((tmp_path / "members").iterdir())


def test_the_content_key_follows_the_physics_and_the_code():
    a, b = _scenes()
    k = runner.member_key(a, {"variant": 1}, "v1")
    assert k == runner.member_key(b, {"variant": 0}, "v1")      # names and rounding aside, one point
    assert k != runner.member_key(a, {"variant": 0}, "v1")      # another point
    assert k != runner.member_key(a, {"variant": 1}, "v2")      # other code
    assert runner.member_key(replace(a, steps=a.steps + 4), {"variant": 1}, "v1") != k
    rough = CATALOGUE["roughness"]
    assert runner.member_key(rough, runner.scene_tasks(rough)[0], "v1") is None  # no content stated: not stored
