#!/usr/bin/env python3
"""Group the failed packs of a run.sh run by cause (the first ": error: " line of each log).

usage: classify.py [WORK [MODE...]]   WORK: the folder run.sh wrote (else the WORK environment variable);
MODE: vk, gl or both (default: gl). Each group shows its size, how many of its pipelines packed for Vulkan,
and one example message.
Not part of the CI suite: it needs a checkout of https://github.com/SaschaWillems/Vulkan (see README.md).
"""
import collections, os, re, sys
work = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("WORK")
modes = sys.argv[2:] or ["gl"]
if not work or not os.path.isfile(os.path.join(work, "pipelines.tsv")):
    sys.exit(f"usage: {sys.argv[0]} WORK [vk|gl|both...]   (WORK: the folder run.sh wrote, with pipelines.tsv)")
log = os.path.join(work, "log")
rows = [l.split("\t")[0] for l in open(os.path.join(work, "pipelines.tsv")) if l.strip()]
def rc(n, m): return int(open(os.path.join(log, f"{n}.{m}.rc")).read())
def cause(line):
    m = line.split(": error: ", 1)[1]
    rules = [
        (r"tessellation is not packed for OpenGL", "GL: tessellation not packed for OpenGL yet"),
        (r"uses input attachments", "GL: input attachments"),
        (r"buffer device addresses", "GL: buffer_reference"),
        (r"uses multiview", "GL: multiview"),
        (r"fragment shading rates", "GL: fragment shading rate"),
        (r"arrays or structs of separate samplers", "GL: SPIRV-Cross: arrays of separate samplers"),
        (r"Debug printf", "GL: SPIRV-Cross: debug printf"),
        (r"does not compile for OpenGL", "GL: GENERATED GLSL DOES NOT COMPILE"),
        (r"SPIRV-Cross cannot translate", "GL: SPIRV-Cross other"),
        (r"which OpenGL 4.5 does not have", "GL: other unsupported feature"),
        (r"\(OpenGL\)", "GL: other"),
        (r"'register' : register type not supported|register", "shader: HLSL register/packoffset"),
        (r"reads '.*' at location \d+, but (vertex|geometry|tessellation|.*) shader .* (does not write|writes)", "notation/pairing: stage interface mismatch"),
        (r"InputLayout", "notation: InputLayout"),
    ]
    for pat, c in rules:
        if re.search(pat, m): return c
    # shader compile error: normalise glslang message
    mm = re.search(r"shader '[^']*'(?: \(OpenGL\))?: (.*)", m)
    t = mm.group(1) if mm else m
    t = re.sub(r"'[^']*'", "'X'", t)
    t = re.sub(r"\[/Pipelines.*", "", t).strip()
    return "compile/other: " + t[:110]
for mode in modes:
    groups = collections.defaultdict(list)
    for n in rows:
        if rc(n, mode) == 0: continue
        lines = [l.strip() for l in open(os.path.join(log, f"{n}.{mode}.log"), errors="replace") if ": error: " in l]
        c = cause(lines[0]) if lines else "no error line"
        groups[c].append((n, lines[0] if lines else ""))
    print(f"##### {mode}: {sum(map(len, groups.values()))} failures")
    for c, v in sorted(groups.items(), key=lambda kv: -len(kv[1])):
        vkok = sum(rc(n, 'vk') == 0 for n, _ in v)
        print(f"[{len(v)}] (vk ok: {vkok}) {c}\n    e.g. {v[0][1][:400]}")
