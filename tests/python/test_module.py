"""The Python module against analytic references (issue 20): the Hertz rigid-flat scene in
process, a dict scene against the closed form of a bar, located errors, compare and sweep.

hertz_rigid_fast.toml: p_max = 383.51 MPa, b = 1.6609 mm (its [reference]); the run's own
figures are asserted against the reference with the tolerances README states for it (0.5 %).
"""
import json
import math
import os
import subprocess
import threading
import tomllib

import numpy as np
import pytest

import contact2d

SOURCE = os.environ.get("C2D_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
HERTZ = os.path.join(SOURCE, "examples", "hertz_rigid_fast.toml")


def bar(E=1000.0, length=4.0, height=1.0, traction=2.0, size=0.5):
    """A plane-stress bar fixed at x = 0 (ux, and uy at one corner), pulled by a traction."""
    return {
        "analysis": {"kind": "plane_stress", "element": "T6"},
        "material": [{"name": "m", "E": E, "nu": 0.0}],
        "body": [{"name": "bar", "material": "m",
                  "shape": {"type": "rectangle", "min": [0.0, 0.0], "max": [length, height]},
                  "mesh": {"size": size}}],
        "support": [{"on": {"body": "bar", "edge": "left"}, "fix": ["ux"]},
                    {"on": {"nearest": [0.0, 0.0]}, "fix": ["uy"]}],
        "load": [{"on": {"body": "bar", "edge": "right"}, "traction": [traction, 0.0]}],
    }


def test_hertz_in_process():
    s = contact2d.run(HERTZ)
    assert s["status"] == "converged"
    ref = s["reference"]
    assert abs(s["contact"]["p_max"] / ref["p_max"] - 1) < 5e-3
    f = s["fields"]
    n = s["mesh"]["nodes"]
    assert f["nodes"].shape == (n, 2) and f["displacement"].shape == (n, 2)
    assert f["stress"].shape == (n, 3)
    assert f["elements"].shape == (s["mesh"]["elements"], 6)
    c = f["contact"]
    # The contact table carries the load: Σ force = the applied 500 N (to 1e-9).
    assert abs(c["force"].sum() / s["contact"]["total_force"] - 1) < 1e-9
    assert abs(c["pressure"].max() - s["contact"]["p_max"]) < 1e-9 * s["contact"]["p_max"]
    assert np.all(np.isfinite(f["displacement"]))


def test_set_and_method_override():
    a = contact2d.run(HERTZ, method="ssn", set=["analysis.mesh_scale=2"])
    b = contact2d.run(HERTZ, method="lagrange", set=["analysis.mesh_scale=2"])
    assert a["method"] == "ssn" and b["method"] == "lagrange"
    assert a["mesh"]["dofs"] < contact2d.run(HERTZ)["mesh"]["dofs"]
    # Two exact methods reach the same solution (1e-9 relative).
    assert abs(a["contact"]["p_max"] / b["contact"]["p_max"] - 1) < 1e-9


def test_dict_scene_against_the_bar_closed_form():
    # u(L) = σ L / E = 2 × 4 / 1000 = 8e-3 at the loaded end (ν = 0: exact for T6).
    s = contact2d.run(bar())
    assert s["status"] == "converged"
    x, u = s["fields"]["nodes"], s["fields"]["displacement"]
    right = np.isclose(x[:, 0], 4.0)
    assert np.allclose(u[right, 0], 8e-3, rtol=1e-9)
    assert np.allclose(s["fields"]["stress"][:, 0], 2.0, rtol=1e-8)


def test_steps_give_a_load_deflection_curve_per_converged_step(tmp_path):
    # A linear bar staged by an amplitude (0 -> 1 by λ = 0.5, then back to 0.5): one row per
    # converged step with the probe and the reactions there. Closed form: u(L) = a σ L / E, and
    # the supports carry the load, Σ reaction_x = -a × traction × height.
    scene = bar()
    scene["analysis"]["steps"] = 4
    scene["load"][0]["amplitude"] = [[0.0, 0.0], [0.5, 1.0], [1.0, 0.5]]
    scene["probe"] = [{"name": "tip", "at": [4.0, 0.5], "quantity": "ux"}]
    out = tmp_path / "staged"
    s = contact2d.run(scene, out=out)
    assert s["status"] == "converged" and s["steps"] == 4
    st = s["fields"]["steps"]
    a = np.array([0.5, 1.0, 0.75, 0.5])
    assert np.allclose(st["load_factor"], [0.25, 0.5, 0.75, 1.0], rtol=0, atol=1e-12)
    assert np.allclose(st["probes"]["tip"], a * 8e-3, rtol=1e-9)
    assert np.allclose(st["reaction_x"], -a * 2.0, rtol=1e-9)
    assert np.allclose(st["reaction_y"], 0.0, atol=1e-9)
    rows = (out / "steps.csv").read_text().splitlines()
    assert rows[0].split(",")[:2] == ["step", "load_factor"] and rows[0].endswith(",tip")
    assert len(rows) == 5
    assert np.allclose([float(r.split(",")[-1]) for r in rows[1:]], a * 8e-3, rtol=1e-9)


def test_bad_input_raises_located_input_error():
    with pytest.raises(contact2d.InputError) as e:
        contact2d.run(HERTZ, set=["analysis.kind=plane_strian"])
    assert "analysis.kind" in str(e.value) and "plane_strain" in str(e.value)
    bad = bar()
    bad["material"][0]["E"] = -1.0
    with pytest.raises(contact2d.InputError) as e:
        contact2d.run(bad)
    assert "<dict>" in str(e.value) and "material[0].E" in str(e.value)
    with pytest.raises(contact2d.InputError):
        contact2d.run(os.path.join(SOURCE, "examples", "no_such_scene.toml"))
    assert issubclass(contact2d.InputError, ValueError)


def test_out_writes_the_run_files(tmp_path):
    out = tmp_path / "run"
    s = contact2d.run(bar(), out=out)
    assert s["status"] == "converged"
    for name in ("summary.json", "nodes.csv"):
        assert (out / name).exists()


def test_adaptive_run_is_the_command_lines(tmp_path):
    # contact2d.run and `contact2d run` share one entry point (app/run/run_scene.hpp): an
    # [adapt] scene refines in process as on the command line, cycle for cycle, to its target.
    scene = os.path.join(SOURCE, "examples", "hertz_rigid_coarse.toml")
    s = contact2d.run(scene, set=["adapt.enabled=true"])
    out = tmp_path / "cli"
    subprocess.run([contact2d.executable(), "run", scene, "--adapt", "--quiet", "--out", str(out)],
                   check=True)
    with open(out / "summary.json") as f:
        cli = json.load(f)
    assert s["status"] == cli["status"] == "converged"
    assert s["adapt"]["reached"] and cli["adapt"]["reached"]
    ours, theirs = s["adapt"]["cycles"], cli["adapt"]["cycles"]
    assert [c["dofs"] for c in ours] == [c["dofs"] for c in theirs]
    assert len(ours) >= 2
    for a, b in zip(ours, theirs):  # the same meshes and solves: the same estimate to round-off
        assert a["relative_error"] == pytest.approx(b["relative_error"], rel=1e-9)
    assert ours[-1]["relative_error"] <= s["adapt"]["target"]  # the scene's η = 2 %


def test_studies_take_dict_scenes_and_a_metric(tmp_path):
    # A dict scene runs as the file it was read from: the same p_max to round-off, judged by the
    # metric asked for (a probe without a reference: against lagrange on the finest level).
    with open(HERTZ, "rb") as f:
        scene = tomllib.load(f)
    scene["probe"] = scene.get("probe", []) + [
        {"name": "top", "quantity": "uy", "at": [0.0, 500.0]}]
    from_dict = contact2d.compare(scene, methods=["lagrange", "penalty"], levels=2,
                                  set=["analysis.mesh_scale=2"], metric="top",
                                  out=tmp_path / "dict")
    from_file = contact2d.compare(HERTZ, methods=["lagrange", "penalty"], levels=2,
                                  set=["analysis.mesh_scale=2"])
    assert (tmp_path / "dict" / "scene.toml").exists()
    assert from_dict["table"]["p_max"] == pytest.approx(from_file["table"]["p_max"], rel=1e-12)
    assert "Judged by the relative difference of probe top" in from_dict["report"]
    assert "(lagrange, level 1)" in from_dict["report"]
    with pytest.raises(contact2d.InputError):
        contact2d.sweep(scene, "contact.penalty.factor", [1e2, 1e4], metric="nonsense")


def test_runs_in_threads():
    # The GIL is released while solving: two threads run their scenes at once (gmsh, which is
    # process-wide, meshes one body at a time), each to the exact answer.
    results = [None, None]

    def work(i):
        results[i] = contact2d.run(bar(size=0.25))

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:  # each thread's bar against the closed form u(L) = σL/E = 8e-3
        assert r["status"] == "converged"
        x, u = r["fields"]["nodes"], r["fields"]["displacement"]
        assert np.allclose(u[np.isclose(x[:, 0], 4.0), 0], 8e-3, rtol=1e-9)


def test_compare_and_sweep_tables():
    c = contact2d.compare(HERTZ, methods=["lagrange", "ssn"], set=["analysis.mesh_scale=2"])
    t = c["table"]
    assert t["method"] == ["lagrange", "ssn"]
    assert all(st == "converged" for st in t["status"])
    assert abs(t["p_max"][0] / t["p_max"][1] - 1) < 1e-9
    assert "Every method ranked reached" in c["report"]
    assert "Judged by the relative L2 error of the pressure profile" in c["report"]
    s = contact2d.sweep(HERTZ, "contact.penalty.factor", [1e2, 1e4], method="penalty",
                        set=["analysis.mesh_scale=2"])
    t = s["table"]
    assert len(t["status"]) == 2 and all(st == "converged" for st in t["status"])
    # A stiffer penalty penetrates less.
    assert t["max_penetration"][1] < t["max_penetration"][0]
    # The penalty factor is held against lagrange on the same mesh (the baseline): the stiffer
    # penalty's p_max is closer to it.
    assert abs(t["error_vs_baseline"][1]) < abs(t["error_vs_baseline"][0])
    assert "Against lagrange on the same mesh" in s["report"]
    with pytest.raises(contact2d.InputError):
        contact2d.compare(HERTZ, methods=["newton"])
    assert not math.isnan(t["p_max"][1])
