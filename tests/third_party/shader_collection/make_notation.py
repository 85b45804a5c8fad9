#!/usr/bin/env python3
"""Pair SaschaWillems/Vulkan shaders (shaders/{glsl,hlsl}/<example>/) into pipelines and write one
statepack notation file per pipeline under WORK/notation/<NAME>.json, NAME = lang__example__pipe.
Also writes WORK/pipelines.tsv (NAME, lang, example, shader dir) and WORK/skipped.txt.
Not part of the CI suite: it needs a checkout of https://github.com/SaschaWillems/Vulkan (see README.md).

Paths (argument, else environment variable, else default):
  --shaders / SHADERS      the collection's shaders folder, with glsl/ and hlsl/ (required)
  --work / WORK            output folder (default: a fresh temporary folder, printed)
  --statepack / STATEPACK  the packager (default: build/bin/statepack under the repository root)
  --examples / EXAMPLES    the collection's examples folder (default: SHADERS/../examples); optional:
                           when present, each EXTRA pipeline is checked against examples/<ex>/<ex>.cpp

InputLayout: a first `statepack pack --check --vulkan` run of each graphics notation (without one) lists
the vertex inputs ("reads 'vec3 inPos' at location 0, but InputLayout has no element ..."); each becomes
one element (BufferSlot 0, FLOAT32/INT32/UINT32 x N; matN: N elements), and the file is rewritten.

Pairing: X.vert [+ X.tesc + X.tese] [+ X.geom] [+ X.frag]; X.comp alone. Plus EXTRA: pipelines the
examples' C++ build from differently named files (read by hand from examples/<ex>/<ex>.cpp loadShader
calls; the table below is what is used, the C++ is only read to warn when the table is out of date).
"""
import argparse, json, os, re, subprocess, sys, tempfile
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
SRC = NOT = WORK = SP = None  # set in main()
SKIP_EXT = {"rgen", "rchit", "rmiss", "rcall", "rahit", "rint", "mesh", "task"}
STAGES = ["vert", "tesc", "tese", "geom", "frag", "comp"]
SLOT = {"vert": ("pVS", "VERTEX"), "tesc": ("pHS", "HULL"), "tese": ("pDS", "DOMAIN"),
        "geom": ("pGS", "GEOMETRY"), "frag": ("pPS", "PIXEL"), "comp": ("pCS", "COMPUTE")}
# example -> list of pipelines {stage: base name}, for files whose names do not pair by the rule
EXTRA = {
    "displacement": [dict(vert="base", tesc="displacement", tese="displacement", frag="base")],
    "tessellation": [dict(vert="base", tesc="pntriangles", tese="pntriangles", frag="base"),
                     dict(vert="base", tesc="passthrough", tese="passthrough", frag="base")],
    "geometryshader": [dict(vert="base", geom="normaldebug", frag="base")],
    "viewportarray": [dict(vert="scene", geom="multiview", frag="scene")],
    "deferredshadows": [dict(vert="shadow", geom="shadow")],  # already by rule; listed for clarity
    "ssao": [dict(vert="fullscreen", frag=f) for f in ("composition", "ssao", "blur")],
    "pbribl": [dict(vert="filtercube", frag=f) for f in ("irradiancecube", "prefilterenvmap")],
    "pbrtexture": [dict(vert="filtercube", frag=f) for f in ("irradiancecube", "prefilterenvmap")],
    "conservativeraster": [dict(vert="triangle", frag="triangleoverlay")],
}


def frag_targets(path, lang):
    text = open(path, errors="replace").read()
    if lang == "GLSL":
        locs = [int(m) for m in re.findall(r"layout\s*\([^)]*location\s*=\s*(\d+)[^)]*\)\s*out\b", text)]
    else:
        locs = [int(m or 0) for m in re.findall(r"SV_TARGET(\d*)", text, re.I)]
    return max(locs) + 1 if locs else 1


def patch_count(path, lang):
    text = open(path, errors="replace").read()
    m = re.search(r"vertices\s*=\s*(\d+)", text) if lang == "GLSL" else re.search(r"outputcontrolpoints\s*\(\s*(\d+)", text)
    return int(m.group(1)) if m else 3


TYPES = {"float": ("FLOAT32", 1), "int": ("INT32", 1), "uint": ("UINT32", 1)}
for n in (2, 3, 4):
    TYPES[f"vec{n}"] = ("FLOAT32", n); TYPES[f"ivec{n}"] = ("INT32", n); TYPES[f"uvec{n}"] = ("UINT32", n)
    TYPES[f"mat{n}"] = ("FLOAT32", n, n)
    TYPES[f"float{n}"] = ("FLOAT32", n); TYPES[f"int{n}"] = ("INT32", n); TYPES[f"uint{n}"] = ("UINT32", n)
    TYPES[f"float{n}x{n}"] = ("FLOAT32", n, n)
UNMAPPED = []


def add_input_layout(row):
    name, lang, ex, d = row
    path = os.path.join(NOT, name + ".json")
    doc = json.load(open(path))
    pipe = doc["Pipelines"][0]
    if "GraphicsPipeline" not in pipe:
        return
    r = subprocess.run([SP, "pack", "--check", "--vulkan", "-t", "1", "-i", name + ".json", "-s", d],
                       cwd=NOT, capture_output=True, text=True, timeout=120)
    elems = {}
    for ty, loc in re.findall(r"reads '(\w+) [^']+' at location (\d+), but InputLayout has no element", r.stderr + r.stdout):
        loc = int(loc)
        if ty not in TYPES:
            UNMAPPED.append(f"{name}: {ty} at {loc}")
            continue
        t = TYPES[ty]
        for i in range(t[2] if len(t) == 3 else 1):
            elems[loc + i] = {"InputIndex": loc + i, "BufferSlot": 0, "NumComponents": t[1], "ValueType": t[0],
                              "IsNormalized": False}
    if elems:
        pipe["GraphicsPipeline"]["InputLayout"] = {"LayoutElements": [elems[k] for k in sorted(elems)]}
        with open(path, "w") as fh:
            json.dump(doc, fh, indent=2)


def check_extra(examples):
    """Warn about EXTRA stage files that examples/<ex>/<ex>.cpp does not name (only if the C++ is there)."""
    if not os.path.isdir(examples):
        print(f"note: no examples folder at {examples}: EXTRA table used without checking it against the C++",
              file=sys.stderr)
        return
    for ex, pipes in EXTRA.items():
        cpp = os.path.join(examples, ex, ex + ".cpp")
        if not os.path.isfile(cpp):
            print(f"warning: EXTRA names example '{ex}', but {cpp} is missing", file=sys.stderr)
            continue
        text = open(cpp, errors="replace").read()
        for p in pipes:
            for s, b in p.items():
                if f'"{ex}/{b}.{s}.spv"' not in text:
                    print(f"warning: EXTRA {ex}: {b}.{s} is not loaded by {cpp}", file=sys.stderr)


def main():
    global SRC, NOT, WORK, SP
    env = os.environ.get
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shaders", default=env("SHADERS"))
    ap.add_argument("--work", default=env("WORK"))
    ap.add_argument("--statepack", default=env("STATEPACK", os.path.join(ROOT, "build", "bin", "statepack")))
    ap.add_argument("--examples", default=env("EXAMPLES"))
    a = ap.parse_args()
    if not a.shaders:
        ap.error("the shaders folder (--shaders or SHADERS) is required")
    if not all(os.path.isdir(os.path.join(a.shaders, d)) for d in ("glsl", "hlsl")):
        ap.error(f"{a.shaders} has no glsl/ and hlsl/ folders")
    if not a.work:
        a.work = tempfile.mkdtemp()
        print(f"WORK={a.work}", file=sys.stderr)
    SRC, WORK, SP = os.path.abspath(a.shaders), os.path.abspath(a.work), os.path.abspath(a.statepack)
    NOT = os.path.join(WORK, "notation")
    check_extra(a.examples or os.path.join(SRC, "..", "examples"))
    os.makedirs(NOT, exist_ok=True)
    rows, skipped, unused = [], [], []
    for lang_dir, lang in (("glsl", "GLSL"), ("hlsl", "HLSL")):
        for ex in sorted(os.listdir(os.path.join(SRC, lang_dir))):
            d = os.path.join(SRC, lang_dir, ex)
            if not os.path.isdir(d):
                continue
            files = sorted(os.listdir(d))
            have = {}  # (base, ext) present
            for f in files:
                base, _, ext = f.rpartition(".")
                if ext in SKIP_EXT:
                    skipped.append(f"{lang_dir}/{ex}/{f}")
                elif ext in STAGES:
                    have[(base, ext)] = f
            pipes = []
            for (base, ext) in sorted(have):
                if ext == "vert":
                    p = {"vert": base}
                    for s in ("tesc", "tese", "geom", "frag"):
                        if (base, s) in have:
                            p[s] = base
                    pipes.append(p)
                elif ext == "comp":
                    pipes.append({"comp": base})
            for p in EXTRA.get(ex, []):
                if all((b, s) in have for s, b in p.items()) and p not in pipes:
                    pipes.append(p)
                    if "tesc" in p or "geom" in p:  # the example uses this vertex shader only with them
                        pipes = [q for q in pipes if q != {"vert": p["vert"], "frag": p["frag"]}]
            used = {(b, s) for p in pipes for s, b in p.items()}
            for k in have:
                if k not in used:
                    unused.append(f"{lang_dir}/{ex}/{have[k]}")
            for p in pipes:
                if "tesc" in p and "tese" not in p or "tese" in p and "tesc" not in p:
                    p.pop("tesc", None); p.pop("tese", None)
                pname = "+".join(f"{b}.{s}" for s, b in sorted(p.items(), key=lambda kv: STAGES.index(kv[0])))
                name = f"{lang_dir}__{ex}__" + "_".join(
                    dict.fromkeys(b for s, b in sorted(p.items(), key=lambda kv: STAGES.index(kv[0]))))
                if "comp" in p:
                    name += "_cs"
                elif "tesc" in p or "geom" in p:
                    name += "_" + "".join(s[0] for s in ("tesc", "geom") if s in p)
                pipe = {"PSODesc": {"Name": f"{lang_dir}/{ex}/{pname}"}}
                if "comp" not in p:
                    gp = {}
                    gp["NumRenderTargets"] = frag_targets(os.path.join(d, have[(p["frag"], "frag")]), lang) if "frag" in p else 0
                    if "tesc" in p:
                        n = patch_count(os.path.join(d, have[(p["tesc"], "tesc")]), lang)
                        gp["PrimitiveTopology"] = f"{n}_CONTROL_POINT_PATCHLIST"
                    pipe["GraphicsPipeline"] = gp
                for s, b in p.items():
                    slot, st = SLOT[s]
                    sh = {"Desc": {"Name": f"{lang_dir}/{ex}/{b}.{s}", "ShaderType": st},
                          "SourceLanguage": lang, "FilePath": have[(b, s)]}
                    if lang == "HLSL":
                        sh["EntryPoint"] = "main"
                    pipe[slot] = sh
                with open(os.path.join(NOT, name + ".json"), "w") as fh:
                    json.dump({"Pipelines": [pipe]}, fh, indent=2)
                rows.append((name, lang, ex, d))
    with ThreadPoolExecutor(2) as pool:
        list(pool.map(add_input_layout, rows))
    with open(os.path.join(WORK, "pipelines.tsv"), "w") as fh:
        for r in rows:
            fh.write("\t".join(r) + "\n")
    with open(os.path.join(WORK, "skipped.txt"), "w") as fh:
        fh.write("# mesh/task/ray-tracing files skipped\n" + "\n".join(skipped) + "\n")
        fh.write("# stage files in no pipeline\n" + "\n".join(unused) + "\n")
        fh.write("# vertex inputs of unmapped type\n" + "\n".join(UNMAPPED) + "\n")
    print(f"{len(rows)} pipelines ({sum(r[1]=='GLSL' for r in rows)} GLSL, {sum(r[1]=='HLSL' for r in rows)} HLSL); "
          f"{len(skipped)} mesh/task/RT files skipped; {len(unused)} stage files unused", file=sys.stderr)


if __name__ == "__main__":
    main()
