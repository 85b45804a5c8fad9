#!/usr/bin/env python3
"""Summarise a run.sh run over the SaschaWillems/Vulkan shader collection.

usage: summarize.py [WORK]   (else the WORK environment variable)

Reads WORK/pipelines.tsv and WORK/log/NAME.MODE.rc (MODE: vk, gl, both, gldemo) and prints, per language
and in all: pipelines tried, Vulkan ok, OpenGL ok, OpenGL ok among Vulkan ok, archives gl_demo linked
(exit 0 and "0 GL error message(s)"), and every crash or timeout (exit >= 124) of statepack or gl_demo.
Exit status 1 if there was any crash or timeout, or a result is missing.
Not part of the CI suite: it needs a checkout of https://github.com/SaschaWillems/Vulkan (see README.md).
"""
import collections, os, re, sys

work = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("WORK")
if not work or not os.path.isfile(os.path.join(work, "pipelines.tsv")):
    sys.exit(f"usage: {sys.argv[0]} WORK   (WORK: the folder run.sh wrote, with pipelines.tsv)")
log = os.path.join(work, "log")
rows = [l.rstrip("\n").split("\t") for l in open(os.path.join(work, "pipelines.tsv")) if l.strip()]


def rc(n, m):
    """Exit status of NAME's MODE run; None if it was not run (no .rc file)."""
    p = os.path.join(log, f"{n}.{m}.rc")
    return int(open(p).read().strip() or -1) if os.path.exists(p) else None


def linked(n):
    p = os.path.join(log, f"{n}.gldemo.log")
    return (rc(n, "gldemo") == 0 and os.path.exists(p)
            and re.search(r"^0 GL error message\(s\)$", open(p, errors="replace").read(), re.M) is not None)


res = {n: dict(lang=lang, vk=rc(n, "vk"), gl=rc(n, "gl"), both=rc(n, "both")) for n, lang, ex, d in rows}
for n, v in res.items():
    v["linked"] = v["gl"] == 0 and linked(n)

renderer = ""
for n, v in res.items():
    p = os.path.join(log, f"{n}.gldemo.log")
    if v["gl"] == 0 and os.path.exists(p):
        renderer = next((l.split(":", 1)[1].strip() for l in open(p, errors="replace") if l.startswith("OpenGL:")), "")
        if renderer:
            break

print(f"OpenGL driver used by gl_demo: {renderer or 'unknown (no gl_demo output)'}")
for lang in ("GLSL", "HLSL", None):
    sel = [v for v in res.values() if lang is None or v["lang"] == lang]
    vk = sum(v["vk"] == 0 for v in sel)
    gl = sum(v["gl"] == 0 for v in sel)
    gl_vk = sum(v["vk"] == 0 and v["gl"] == 0 for v in sel)
    both = sum(v["both"] == 0 for v in sel)
    print(f"{lang or 'ALL':4}: tried {len(sel)}, Vulkan ok {vk}, OpenGL ok {gl}, OpenGL ok among Vulkan ok "
          f"{gl_vk}/{vk}, both flags ok {both}, linked by gl_demo {sum(v['linked'] for v in sel)}/{gl}")

bad, missing = [], []
for n, v in res.items():
    for m in ("vk", "gl", "both") + (("gldemo",) if v["gl"] == 0 else ()):
        r = rc(n, m)
        if r is None:
            missing.append(f"{n}.{m}")
        elif r >= 124 or r < 0:
            bad.append(f"{n}.{m} (exit {r}{', timeout' if r == 124 else ''})")
# --vulkan --opengl together must succeed exactly when each flag alone does
mism = [n for n, v in res.items() if v["both"] is not None and (v["both"] == 0) != (v["vk"] == 0 and v["gl"] == 0)]
unlinked = [n for n, v in res.items() if v["gl"] == 0 and not v["linked"]]

print("exit status histogram: " + ", ".join(
    f"{m} {dict(sorted(collections.Counter(v[m] for v in res.values() if v[m] is not None).items()))}"
    for m in ("vk", "gl", "both")))
print(f"crashes/timeouts (exit >= 124): {len(bad)}" + "".join(f"\n  {b}" for b in bad))
if missing:
    print(f"results missing: {len(missing)}" + "".join(f"\n  {m}" for m in missing[:20]))
if mism:
    print(f"both flags disagree with the two single-flag runs: {len(mism)}" + "".join(f"\n  {m}" for m in mism))
if unlinked:
    print(f"OpenGL archives gl_demo did not link cleanly: {len(unlinked)} (see log/NAME.gldemo.log)"
          + "".join(f"\n  {m}" for m in unlinked))
sys.exit(1 if bad or missing else 0)
