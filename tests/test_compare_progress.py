"""validation.compare around the scenes: stale temporary directories of killed runs are
removed, progress never stops for long and goes to stderr with --json - (issue 12)."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time

from validation import compare, report
from validation.catalogue import CATALOGUE
from validation.sources import code_version


def _dead_pid() -> int:
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_stale_temporary_scene_directories_are_removed(tmp_path):
    root = tmp_path / "scenes"
    old = time.time() - 2 * compare.STALE_TMP_S
    made = {}
    for key, name in [("killed", ".sphere-md.k3x_9q"), ("live", ".sphere-md.a1b2c3"),
                      ("dead_old", f".sphere-md.old.{_dead_pid()}"), ("own_old", f".sphere-md.old.{os.getpid()}"),
                      ("other_scene", ".geom-flat.zz9"), ("prefix_scene", ".sphere-md-x.abc"),
                      ("odd_name", ".sphere-md.a b")]:
        d = root / name
        d.mkdir(parents=True)
        (d / "result.json").write_text("{}")
        made[key] = d
    for key in ("killed", "other_scene", "prefix_scene", "odd_name"):
        os.utime(made[key], (old, old))
    (root / ".sphere-md.file").write_text("not a directory")
    os.utime(root / ".sphere-md.file", (old, old))
    logged = []
    removed = compare.remove_stale_tmp(tmp_path, ["sphere-md"], log=logged.append)
    assert sorted(removed) == sorted([made["killed"], made["dead_old"]])
    for key in ("live", "own_old", "other_scene", "prefix_scene", "odd_name"):
        assert made[key].is_dir(), key
    assert (root / ".sphere-md.file").is_file()
    assert len(logged) == 2 and all("interrupted run" in m for m in logged)
    assert compare.remove_stale_tmp(tmp_path / "nothing", ["sphere-md"]) == []


def test_run_all_cleans_up_before_it_runs(tmp_path):
    s = CATALOGUE["sphere-md"]
    d = tmp_path / "scenes" / s.name
    d.mkdir(parents=True)
    (d / "result.json").write_text(json.dumps({"fingerprint": s.fingerprint(code_version())}))
    stale = tmp_path / "scenes" / f".{s.name}.q1w2e3"
    stale.mkdir()
    old = time.time() - 2 * compare.STALE_TMP_S
    os.utime(stale, (old, old))
    logged = []
    assert compare.run_all([s], tmp_path, log=logged.append) == {s.name: "skipped"}
    assert not stale.exists() and d.is_dir()
    assert logged[0].startswith("[clean] removed")


def test_heartbeat_speaks_when_nothing_else_does():
    lines = []
    with compare.Heartbeat(lines.append, interval=0.2) as say:
        say("[geom-flat] fem a/80 ...")
        time.sleep(0.75)
    beats = [m for m in lines if "still working" in m]
    assert lines[0] == "[geom-flat] fem a/80 ..." and 2 <= len(beats) <= 4
    assert "last: [geom-flat] fem a/80" in beats[0]
    n = len(lines)
    time.sleep(0.4)
    assert len(lines) == n  # stopped with the block


def test_hard_cases_progress_goes_to_stderr_with_json_stdout(tmp_path, monkeypatch, capsys):
    """Each hard case is named on stderr as it starts (and the heartbeat covers a long one);
    stdout holds only the JSON."""
    import validation.hard_cases as hc

    def fake_hard_cases(quick=True, cache_dir=None, log=None):
        for name in ("flat punch", "truncated edge"):
            log(name)
            time.sleep(0.5)
        return []

    def fake_run_all(scenes, out, log=print, **kw):
        log("[skip] sphere-md: unchanged since the last run (--force reruns)")
        return {s.name: "skipped" for s in scenes}

    def fake_write_report(out, names, status, *, hard_cases=None, json_path=None, quick=False, executor=None, **kw):
        if json_path == "-":
            sys.stdout.write(json.dumps({"status": status}) + "\n")
        return tmp_path / "report.md"

    monkeypatch.setattr(hc, "hard_cases", fake_hard_cases)
    monkeypatch.setattr(compare, "run_all", fake_run_all)
    monkeypatch.setattr(report, "write_report", fake_write_report)
    monkeypatch.setattr(compare, "HEARTBEAT_S", 0.2)
    rc = compare.main(["--quick", "--scenes", "sphere-md", "--out", str(tmp_path), "--json", "-"])
    cap = capsys.readouterr()
    assert rc == 0
    assert json.loads(cap.out) == {"status": {"sphere-md": "skipped"}}
    err = cap.err.splitlines()
    i = err.index("  hard case: flat punch")
    assert err[i + 1:].index("  hard case: truncated edge") >= 1  # a heartbeat between the two
    assert any("still working" in m and "hard case: flat punch" in m for m in err[i:])
