#!/usr/bin/env python3
"""Compiles every entry point of DiligentFX's shaders with statepack, one standalone shader at a time.

Not part of the CI suite (it needs a DiligentFX checkout). Usage, from the repository root:

    tests/third_party/diligent_samples/effects.py /path/to/DiligentFX [build-dir] [-- extra pack options]

Entry points are found in each shader file (.fx, .psh, .vsh, .csh; .fxh files are headers): a function
with an SV_Target or SV_Depth parameter or result is a pixel shader, one after [numthreads(...)] a
compute shader, a function named ...PS, ...VS or ...CS a pixel, vertex or compute shader, and `main` of
a .psh, .vsh or .csh takes the file's stage (files that only define functions for others to include give
none). Each becomes a notation file with that one shader (HLSL, no macros: the C++ that sets some is not
read), packed with --vulkan, with every folder of Shaders/ as a shader directory. (OpenGL archives hold
pipelines only, and a pipeline needs what the C++ pairs; the tutorials' check covers OpenGL.) The summary
counts the shaders and groups the failures by their first error message.

Exit status: 0 when every run ended, 1 when a statepack run crashed or timed out, 2 on a usage error.
Nothing is written into the checkout.
"""
import json
import os
import re
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

FUNCTION = re.compile(r"^[ \t]*(?:\[[^\]\n]*\][ \t]*\n?[ \t]*)*([A-Za-z_]\w*)[ \t]+([A-Za-z_]\w*)[ \t]*\(", re.M)
STAGE_OF_EXTENSION = {".psh": "PIXEL", ".vsh": "VERTEX", ".csh": "COMPUTE"}


def signature(text, open_paren):
    """The text from the parameter list's '(' to the body's '{' (or a ';' of a declaration)."""
    depth = 0
    for i in range(open_paren, len(text)):
        if text[i] == "(":
            depth += 1
        elif text[i] == ")":
            depth -= 1
            if depth == 0:
                end = i
                while end < len(text) and text[end] not in "{;":
                    end += 1
                return text[open_paren:end] if end < len(text) and text[end] == "{" else None
    return None


def entry_points(path):
    text = re.sub(r"//[^\n]*", "", path.read_text(errors="replace"))
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    found = []
    for m in FUNCTION.finditer(text):
        result, name = m.group(1), m.group(2)
        if result in ("return", "else", "if", "struct", "cbuffer"):
            continue
        sig = signature(text, m.end() - 1)
        if sig is None:
            continue
        before = text[max(0, m.start() - 200):m.start()]
        if "numthreads" in m.group(0) or re.search(r"\[numthreads\([^)]*\)\]\s*$", before):
            stage = "COMPUTE"
        elif "SV_Target" in sig or "SV_Depth" in sig:
            stage = "PIXEL"
        elif name.endswith("PS"):
            stage = "PIXEL"
        elif name.endswith("VS"):
            stage = "VERTEX"
        elif name.endswith("CS"):
            stage = "COMPUTE"
        elif name == "main" and path.suffix in STAGE_OF_EXTENSION:
            stage = STAGE_OF_EXTENSION[path.suffix]
        else:
            continue
        found.append((name, stage))
    return found


def first_error(output):
    for line in output.splitlines():
        if "error:" in line:
            message = line.split("error:", 1)[1].strip()
            message = re.sub(r"^(shader|pipeline) '[^']*': ", "", message)
            return re.sub(r"^[^:]*\.(fx|fxh|psh|vsh|csh|hlsl)(:\d+)*: ", "", message)[:160]
    return output.strip().splitlines()[-1][:160] if output.strip() else "(no output)"


def main(argv):
    extra = []
    if "--" in argv:
        extra = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    if len(argv) not in (2, 3):
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    shaders_root = Path(argv[1]) / "Shaders"
    statepack = Path(argv[2] if len(argv) == 3 else "build") / "bin" / "statepack"
    if not shaders_root.is_dir() or not os.access(statepack, os.X_OK):
        print(f"effects.py: need {shaders_root}/ and an executable {statepack}", file=sys.stderr)
        return 2
    dirs = sorted(str(d) for d in shaders_root.rglob("*") if d.is_dir()) + [str(shaders_root)]
    search = [arg for d in dirs for arg in ("-s", d)]
    shaders = []
    for path in sorted(shaders_root.rglob("*")):
        if path.suffix in (".fx", ".psh", ".vsh", ".csh"):
            for name, stage in entry_points(path):
                shaders.append((path.relative_to(shaders_root), name, stage))
    compiled = 0
    failures = defaultdict(list)
    broken = False
    with tempfile.TemporaryDirectory() as work:
        for rel, entry, stage in shaders:
            label = f"{rel}:{entry} ({stage.lower()})"
            notation = Path(work) / "shader.json"
            notation.write_text(json.dumps({"Shaders": [{
                "Desc": {"Name": f"{rel.stem} {entry}", "ShaderType": stage},
                "SourceLanguage": "HLSL", "FilePath": str(rel), "EntryPoint": entry}]}))
            run = subprocess.run([str(statepack), "pack", "-i", str(notation), *search, "-o",
                                  str(Path(work) / "vulkan.spk"), "--vulkan", *extra],
                                 capture_output=True, text=True, timeout=600)
            broken = broken or run.returncode >= 124 or run.returncode < 0
            if run.returncode == 0:
                compiled += 1
            else:
                failures[first_error(run.stdout + run.stderr)].append(label)
            print(f"vulkan {'PASS' if run.returncode == 0 else 'FAIL'}  {label}", flush=True)
    files = len({s[0] for s in shaders})
    print(f"\nshaders tried:                {len(shaders)} (entry points of {files} files)")
    print(f"compiled for Vulkan:          {compiled}")
    if failures:
        print("\nfailures, grouped by the first error message (count = shaders):")
        for message, who in sorted(failures.items(), key=lambda kv: -len(kv[1])):
            print(f"  [{len(who)}] {message}")
            for w in who[:6]:
                print(f"        {w}")
            if len(who) > 6:
                print(f"        ... and {len(who) - 6} more")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
