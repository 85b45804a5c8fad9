#!/usr/bin/env python3
"""Helpers of run.sh (see README.md).

  helper.py split NOTATION OUTDIR   one notation file per pipeline: OUTDIR/NN.json; prints "NN<TAB>name" lines
  helper.py summary RESULTS.tsv     the counts and the failures grouped by their first error message
  helper.py first-error LOG         the first error of a statepack pack log, as the summary groups it

split keeps the file's Defaults and only the named resource signatures, render passes and shaders
the pipeline refers to, so that each pipeline packs (or fails) on its own: statepack writes nothing
when any object of a file has an error.
"""
import collections
import json
import os
import re
import sys

SLOTS = ("pVS", "pPS", "pGS", "pHS", "pDS", "pCS", "pAS", "pMS")


def split(notation, outdir):
    with open(notation, encoding="utf-8") as f:
        doc = json.load(f, object_pairs_hook=collections.OrderedDict)
    os.makedirs(outdir, exist_ok=True)
    defaults = doc.get("Defaults", {})
    default_sigs = defaults.get("Pipeline", {}).get("ppResourceSignatures", []) if isinstance(defaults, dict) else []
    for i, pipeline in enumerate(doc.get("Pipelines", [])):
        sigs = {s for s in list(pipeline.get("ppResourceSignatures", [])) + list(default_sigs) if isinstance(s, str)}
        passes = set()
        rp = pipeline.get("GraphicsPipeline", {}).get("pRenderPass")
        if isinstance(rp, str):
            passes.add(rp)
        shaders = {pipeline[s] for s in SLOTS if isinstance(pipeline.get(s), str)}
        part = collections.OrderedDict()
        for key, value in doc.items():
            if key == "Pipelines":
                part[key] = [pipeline]
            elif key == "ResourceSignatures":
                kept = [s for s in value if s.get("Name") in sigs]
                if kept:
                    part[key] = kept
            elif key == "RenderPasses":
                kept = [r for r in value if r.get("Name") in passes]
                if kept:
                    part[key] = kept
            elif key == "Shaders":
                kept = [s for s in value if s.get("Desc", {}).get("Name") in shaders]
                if kept:
                    part[key] = kept
            elif key == "Ignore":
                continue
            else:
                part[key] = value
        name = "%02d" % i
        with open(os.path.join(outdir, name + ".json"), "w", encoding="utf-8") as f:
            json.dump(part, f, indent=4)
            f.write("\n")
        print("%s\t%s" % (name, pipeline.get("PSODesc", {}).get("Name", "?")))


LOCATION = re.compile(r"^.*?:\d+(?::\d+)?: error: ")
POINTER = re.compile(r" \[/[^\]]*\]$")
OWNER = re.compile(r"^(?:shaders? '[^']*'(?: and '[^']*')?(?: \(OpenGL\))?|pipeline '[^']*'): ")


def first_error(log, kind):
    """The first error of a statepack log, without its file position, JSON pointer and owner prefix."""
    try:
        with open(log, encoding="utf-8", errors="replace") as f:
            lines = [l.rstrip("\n") for l in f]
    except OSError:
        return "(no log)"
    if kind == "verify":
        for l in lines:
            if l.startswith("FAILED "):
                m = re.match(r"FAILED [^']*'[^']*'(?: with [^:]*)?: (.*)$", l)
                return m.group(1) if m else l
    for l in lines:
        if ": error: " in l or l.startswith("error: "):
            msg = LOCATION.sub("", l)
            if msg.startswith("error: "):
                msg = msg[len("error: "):]
            msg = POINTER.sub("", msg)
            return OWNER.sub("", msg)
    rest = [l for l in lines if l.strip()]
    return rest[-1] if rest else "(no output)"


def summary(results):
    rows = []
    with open(results, encoding="utf-8") as f:
        for line in f:
            tut, name, vk, gl, ver, logdir = line.rstrip("\n").split("\t")
            rows.append((tut, name, int(vk), int(gl), ver, logdir))
    tried = len(rows)
    vk_ok = sum(1 for r in rows if r[2] == 0)
    gl_ok = sum(1 for r in rows if r[3] == 0)
    ver_ok = sum(1 for r in rows if r[4] == "0")
    print("pipelines tried:                      %d" % tried)
    print("packed for Vulkan (--vulkan):         %d" % vk_ok)
    print("packed for OpenGL (--opengl):         %d" % gl_ok)
    print("verified (statepack verify, Vulkan):  %d" % ver_ok)
    groups = collections.OrderedDict()
    for tut, name, vk, gl, ver, logdir in rows:
        checks = []
        if vk != 0:
            checks.append(("vulkan", first_error(os.path.join(logdir, "vulkan.log"), "pack")))
        if gl != 0:
            checks.append(("opengl", first_error(os.path.join(logdir, "opengl.log"), "pack")))
        if ver not in ("0", "-"):
            checks.append(("verify", first_error(os.path.join(logdir, "verify.log"), "verify")))
        for kind, msg in checks:
            groups.setdefault(msg, collections.OrderedDict()).setdefault("%s: '%s'" % (tut, name), []).append(kind)
    if not groups:
        print("no failures")
        return
    print()
    print("failures, grouped by the first error message (count = pipelines):")
    for msg, members in sorted(groups.items(), key=lambda kv: (-len(kv[1]), kv[0])):
        print("  [%d] %s" % (len(members), msg))
        for member, kinds in members.items():
            print("        %s (%s)" % (member, ", ".join(kinds)))


def main(argv):
    if len(argv) == 4 and argv[1] == "split":
        split(argv[2], argv[3])
    elif len(argv) == 3 and argv[1] == "summary":
        summary(argv[2])
    elif len(argv) == 3 and argv[1] == "first-error":
        print(first_error(argv[2], "pack"))
    else:
        sys.stderr.write(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
