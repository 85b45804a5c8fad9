#!/usr/bin/env python3
"""Fails when a function of packager/, dearchiver/ or samples/ runs past the line limit (120).

A function here is what clang-format leaves at column 0: a line that is not a comment, preprocessor
line, namespace, type or closing brace, holds '(' and opens a body with '{' (on that line or a later
signature line); it ends at the next '}' at column 0. Lambdas and nested types count toward the
function they sit in. Usage: function_length.py <source root> [limit]
"""
import os
import sys

SKIP = ('//', '#', '}', 'namespace', 'using', 'struct', 'class', 'enum', 'template', 'extern', 'static_assert')


def long_functions(path, limit):
    lines = open(path, encoding='utf-8', errors='replace').read().split('\n')
    i = 0
    while i < len(lines):
        line = lines[i]
        if line and not line[0].isspace() and not line.startswith(SKIP) and '(' in line:
            j = i
            while j < len(lines) and not lines[j].rstrip().endswith(('{', ';')):
                j += 1
            if j < len(lines) and lines[j].rstrip().endswith('{'):
                k = j + 1
                while k < len(lines) and lines[k] != '}':
                    k += 1
                if k - i + 1 > limit:
                    yield i + 1, k - i + 1, line.strip()
                i = k
        i += 1


def main():
    root = sys.argv[1]
    limit = int(sys.argv[2]) if len(sys.argv) > 2 else 120
    found = []
    checked = 0
    for room in ('packager', 'dearchiver', 'samples'):
        for directory, _, files in os.walk(os.path.join(root, room)):
            for name in sorted(files):
                if name.endswith(('.cpp', '.hpp')):
                    path = os.path.join(directory, name)
                    checked += 1
                    for line, length, signature in long_functions(path, limit):
                        found.append(f'{os.path.relpath(path, root)}:{line}: {length} lines: {signature[:100]}')
    if checked == 0:
        sys.exit('FAIL: no sources found under ' + root)
    for f in found:
        print(f)
    if found:
        sys.exit(f'FAIL: {len(found)} function(s) over {limit} lines; split them at their seams')
    print(f'{checked} files, no function over {limit} lines')


if __name__ == '__main__':
    main()
