#!/usr/bin/env python3
"""Meshes thin and degenerate shapes with `contact2d mesh` (issue 32, item 5): every exit code
must be 0, 1 or 2; a signal (gmsh aborting the process) or a hang is a failure.

Usage: thin_shape_sweep.py CONTACT2D WORK_DIR [TIMEOUT_S [NAME_PREFIX | all-but-rect]]
Sizes equal to a rectangle's thickness make legitimate meshes of up to ~1e6 triangles (slow).
"""
import itertools, math, subprocess, sys, collections

exe, work = sys.argv[1], sys.argv[2]
HEAD = '[[material]]\nname = "m"\nE = 1000.0\nnu = 0.3\n[[body]]\nname = "b"\nmaterial = "m"\n'

def scenes():
    for L, rel, hrel in itertools.product([1e-3, 1.0, 20.0, 40.0, 1e4],
                                          [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9,
                                           1e-10, 1e-11, 1e-12],
                                          [1 / 40, 1.0, 10.0, None]):
        t = L * rel
        h = t if hrel is None else L * hrel
        yield f"rect L={L:g} t={t:g} h={h:g}", (
            f'shape = {{ type = "rectangle", min = [0.0, 0.0], max = [{L!r}, {t!r}] }}\n'
            f'mesh = {{ size = {h!r} }}\n')
    for t in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]:
        yield f"rect abs 40 x {t:g}", (
            f'shape = {{ type = "rectangle", min = [0.0, 0.0], max = [40.0, {t!r}] }}\n'
            'mesh = { size = 1.0 }\n')
        yield f"rect offset x 1e6, t={t:g}", (
            f'shape = {{ type = "rectangle", min = [1e6, 0.0], max = [1000020.0, {t!r}] }}\n'
            'mesh = { size = 1.0 }\n')
        yield f"tiny square {t:g}", (
            f'shape = {{ type = "rectangle", min = [0.0, 0.0], max = [{t!r}, {t!r}] }}\n'
            f'mesh = {{ size = {t / 4!r} }}\n')
        yield f"thin triangle {t:g}", (
            f'shape = {{ type = "polygon", points = [[0.0, 0.0], [20.0, 0.0], [0.0, {t!r}]] }}\n'
            'mesh = { size = 0.5 }\n')
        yield f"spike polygon {t:g}", (
            'shape = { type = "polygon", points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], '
            f'[0.5, 1.0], [0.5, 20.0], [{0.5 - t!r}, 1.0], [0.0, 1.0]] }}\n'
            'mesh = { size = 0.1 }\n')
        yield f"near-collinear quad {t:g}", (
            f'shape = {{ type = "polygon", points = [[0.0, 0.0], [10.0, {t!r}], [20.0, 0.0], '
            f'[10.0, {2 * t!r}]] }}\nmesh = {{ size = 0.5 }}\n')
        yield f"near-repeated vertex {t:g}", (
            f'shape = {{ type = "polygon", points = [[0.0, 0.0], [1.0, 0.0], [{1.0 + t!r}, 0.0], '
            '[1.0, 1.0], [0.0, 1.0]] }\nmesh = { size = 0.1 }\n')
        yield f"almost touching edges {t:g}", (
            'shape = { type = "polygon", points = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], '
            f'[1.1, 2.0], [1.1, {t!r}], [0.9, {t!r}], [0.9, 2.0], [0.0, 2.0]] }}\n'
            'mesh = { size = 0.1 }\n')
        yield f"disk r={t:g}", (
            f'shape = {{ type = "disk", center = [0.0, 0.0], radius = {t!r} }}\n'
            f'mesh = {{ size = {t / 4!r} }}\n')
        yield f"disk r={t:g} offset 1e3", (
            f'shape = {{ type = "disk", center = [1e3, 0.0], radius = {t!r} }}\n'
            f'mesh = {{ size = {t / 4!r} }}\n')
        yield f"disk_segment angle {t:g} deg", (
            'shape = { type = "disk_segment", center = [0.0, 0.0], radius = 1.0, from_deg = 10.0, '
            f'to_deg = {10.0 + t!r} }}\nmesh = {{ size = 0.05 }}\n')
        yield f"disk_segment 360-{t:g} deg", (
            'shape = { type = "disk_segment", center = [0.0, 0.0], radius = 1.0, from_deg = 0.0, '
            f'to_deg = {360.0 - t!r} }}\nmesh = {{ size = 0.05 }}\n')
    for h in [1e2, 1e4, 1e8]:
        yield f"disk size {h:g} x radius", (
            f'shape = {{ type = "disk", center = [0.0, 0.0], radius = 1.0 }}\nmesh = {{ size = {h!r} }}\n')
        yield f"disk_segment 1 deg size {h:g}", (
            'shape = { type = "disk_segment", center = [0.0, 0.0], radius = 1.0, from_deg = 0.0, '
            f'to_deg = 1.0 }}\nmesh = {{ size = {h!r} }}\n')

codes = collections.Counter()
bad = []
only = sys.argv[4] if len(sys.argv) > 4 else ""
for i, (name, body) in enumerate(scenes()):
    if only and not name.startswith(only) and only != "all-but-rect":
        continue
    if only == "all-but-rect" and name.startswith("rect L="):
        continue
    path = f"{work}/s{i}.toml"
    open(path, "w").write(HEAD + body)
    try:
        r = subprocess.run([exe, "mesh", path, "--out", f"{work}/o{i}"], capture_output=True,
                           text=True, timeout=float(sys.argv[3]) if len(sys.argv) > 3 else 120)
        rc = r.returncode
        msg = (r.stderr.strip().splitlines() or [""])[-1]
        if rc == 0:
            msg = " ".join(r.stdout.split()[:12])
    except subprocess.TimeoutExpired:
        rc, msg = "timeout", ""
    codes[rc] += 1
    print(f"{rc!s:>7}  {name:40s} {msg[:150]}", flush=True)
    if rc not in (0, 1, 2):
        bad.append((name, rc))
print("exit codes:", dict(codes))
print("process killed or hung:", bad if bad else "none")
sys.exit(1 if bad else 0)
