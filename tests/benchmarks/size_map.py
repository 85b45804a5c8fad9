#!/usr/bin/env python3
"""Where the bytes of a program go: the symbols of an unstripped binary (nm -S -C) summed by the room
of statepack they come from (or std / other), the largest symbols, and the sizes of the ELF sections
(size -A) that hold what no symbol names (unwind tables, relocations, strings).

Usage: size_map.py <unstripped program> [top N]   (bench_size runs it on min_dearchiver)"""
import collections
import re
import subprocess
import sys

ROOMS = [  # the first pattern that matches names the room
    (r"statepack::bootstrap", "bootstrap (the program's device setup)"),
    (r"nlohmann", "nlohmann-json (variants files)"),
    (r"capability", "SPIR-V capability table"),
    (r"statepack::spirv::grammar", "SPIR-V grammar tables"),
    (r"statepack::spirv", "SPIR-V walker and structure check"),
    (r"statepack::format", "archive format (decode, checks)"),
    (r"statepack::detail::(Planner|plan_|check_|Checker|settle|variant_key)", "runtime: planning and checks"),
    (r"statepack::detail", "runtime: other internals"),
    (r"statepack::", "public API"),
    (r"XXH|xxh", "xxhash"),
    (r"std::|__gnu|__cxx", "standard library templates"),
]


def room(name):
    for pattern, label in ROOMS:
        if re.search(pattern, name):
            return label
    return "other"


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    program, top = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 15
    symbols = subprocess.run(["nm", "-S", "--size-sort", "-C", program], check=True, capture_output=True,
                             text=True).stdout.splitlines()
    rooms, largest = collections.Counter(), []
    for line in symbols:
        parts = line.split(" ", 3)
        if len(parts) < 4 or parts[2] in "Uuw":
            continue
        size, name = int(parts[1], 16), parts[3]
        rooms[room(name)] += size
        largest.append((size, name))
    total = sum(rooms.values())
    print(f"{program}: {total:,} bytes in named symbols")
    print("| room | bytes | share |\n|---|---|---|")
    for label, size in rooms.most_common():
        print(f"| {label} | {size:,} | {100 * size / total:.1f} % |")
    print(f"\nlargest {top} symbols:\n| bytes | symbol |\n|---|---|")
    for size, name in sorted(largest, reverse=True)[:top]:
        print(f"| {size:,} | `{name[:100]}` |")
    sections = subprocess.run(["size", "-A", program], check=True, capture_output=True, text=True).stdout
    print("\nallocated sections (size -A; .text and .rodata hold the symbols above):\n| section | bytes |\n|---|---|")
    for line in sections.splitlines():
        fields = line.split()
        if len(fields) == 3 and fields[0].startswith(".") and fields[1].isdigit() and int(fields[2]) != 0:
            print(f"| {fields[0]} | {int(fields[1]):,} |")


if __name__ == "__main__":
    main()
