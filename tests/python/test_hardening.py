"""The Python module leaves its host process alone and refuses hostile input with located
errors (issue 32, items 1 and 2): Ctrl-C still raises KeyboardInterrupt after a run with `out`,
a run interrupted midway raises it without finishing (no output or work folder left), deep or
oversized scene values and a one-string `set` are InputErrors naming their place; a file of `out`
that cannot be written raises OSError naming the output folder (the command line's exit 3).
"""
import errno
import os
import subprocess
import sys
import textwrap

import pytest

import contact2d

SOURCE = os.path.abspath(os.environ.get("C2D_SOURCE_DIR",
                                        os.path.join(os.path.dirname(__file__), "..", "..")))
CATTANEO = os.path.join(SOURCE, "examples", "cattaneo_mindlin.toml")
HERTZ = os.path.join(SOURCE, "examples", "hertz_rigid_fast.toml")


def bar():
    return {
        "analysis": {"kind": "plane_stress", "element": "T3"},
        "material": [{"name": "m", "E": 1000.0, "nu": 0.0}],
        "body": [{"name": "bar", "material": "m",
                  "shape": {"type": "rectangle", "min": [0.0, 0.0], "max": [4.0, 1.0]},
                  "mesh": {"size": 0.5}}],
        "support": [{"on": {"body": "bar", "edge": "left"}, "fix": ["ux"]},
                    {"on": {"nearest": [0.0, 0.0]}, "fix": ["uy"]}],
        "load": [{"on": {"body": "bar", "edge": "right"}, "traction": [2.0, 0.0]}],
    }


def python(script, tmp_path):
    """Runs `script` in a fresh interpreter with this module; returns the completed process."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.dirname(os.path.dirname(os.path.abspath(contact2d.__file__)))
    return subprocess.run([sys.executable, "-c", textwrap.dedent(script)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120)


def test_ctrl_c_after_a_run_with_out_raises_keyboard_interrupt(tmp_path):
    # Before: RunOutput::commit() reset SIGINT to SIG_DFL and the signal killed the interpreter.
    p = python("""
        import os, signal, contact2d
        s = contact2d.run(%r, out="run")
        assert s["status"] == "converged"
        try:
            os.kill(os.getpid(), signal.SIGINT)
            print("not raised")
        except KeyboardInterrupt:
            print("caught")
        """ % HERTZ, tmp_path)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "caught"


def test_ctrl_c_during_a_run_stops_it_and_leaves_no_folder(tmp_path):
    # cattaneo_mindlin takes several seconds; a signal after 1 s must stop it there: with `out`,
    # a run that finished would have put its folder in place, an interrupted one leaves none.
    p = python("""
        import os, signal, threading, contact2d
        threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
        try:
            contact2d.run(%r, out="run")
            print("finished")
        except KeyboardInterrupt:
            print("interrupted")
        """ % CATTANEO, tmp_path)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "interrupted"
    assert os.listdir(tmp_path) == []  # neither run/ nor run.part.PID


def deep(levels):
    d = {"x": 1}
    for _ in range(levels):
        d = {"a": d}
    return d


def test_deeply_nested_scene_is_refused_with_its_path():
    scene = bar()
    scene["extra"] = deep(100000)  # before: a C++ stack overflow (SIGSEGV)
    with pytest.raises(contact2d.InputError) as e:
        contact2d.run(scene)
    assert "extra.a.a" in str(e.value) and "nested at most" in str(e.value)
    listed = bar()
    nested = [1]
    for _ in range(100000):
        nested = [nested]
    listed["extra"] = nested
    with pytest.raises(contact2d.InputError) as e:
        contact2d.run(listed)
    assert "extra[0][0]" in str(e.value)


def test_integer_beyond_64_bits_is_refused_with_its_key():
    scene = bar()
    scene["material"][0]["E"] = 2 ** 70
    with pytest.raises(contact2d.InputError) as e:
        contact2d.run(scene)
    assert "material[0].E" in str(e.value) and "64 bits" in str(e.value)


def test_empty_out_is_refused():
    with pytest.raises(contact2d.InputError) as e:
        contact2d.run(bar(), out="")
    assert str(e.value).startswith("out: expected a folder name")


def test_one_string_set_is_one_override():
    # Before: set="abc" became three overrides "a", "b", "c".
    with pytest.raises(contact2d.InputError) as e:
        contact2d.run(bar(), set="analysis.kind=plane_strian")
    assert "analysis.kind" in str(e.value)
    s = contact2d.run(bar(), set="analysis.element=T6")
    assert s["status"] == "converged" and s["mesh"]["element"] == "T6"
    with pytest.raises(contact2d.InputError) as e:
        contact2d.run(bar(), set=[1])
    assert "set[0]" in str(e.value)


def test_write_failure_raises_oserror_naming_the_output_folder(tmp_path):
    # A full disk, made so that it fails for root too: files may not grow beyond 4 kB
    # (RLIMIT_FSIZE, SIGXFSZ ignored so write() fails with EFBIG). The run's first VTU is larger.
    # Before: RuntimeError "<tmp>/run.part.PID/step_0001.vtu: cannot write: File too large".
    p = python("""
        import errno, resource, signal, contact2d
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))
        try:
            contact2d.run(%r, out="run")
            print("no error")
        except OSError as e:
            print(type(e).__name__, e.errno == errno.EFBIG)
            print(e.strerror)
        """ % HERTZ, tmp_path)
    assert p.returncode == 0, p.stderr
    kind, message = p.stdout.strip().split("\n")
    assert kind == "OSError True"
    assert message.startswith("run: cannot write the run's ")
    assert message.endswith(": " + os.strerror(errno.EFBIG) + " (nothing of this run was kept)")
    assert ".part" not in message
    assert os.listdir(tmp_path) == []  # neither run/ nor run.part.PID
