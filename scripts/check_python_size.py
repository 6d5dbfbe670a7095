#!/usr/bin/env python3
"""Check that no function or method in addon/**/*.py is longer than 80 lines.

A long function hides the steps a reader must follow; split it into named steps. The Python
counterpart of scripts/check_function_size.sh for the solver. A function counts from its `def`
line to its last line. One may stay longer only with a comment on the line before it (before
its first decorator, if it has any) that gives the reason:
    # long-function: <why this one reads better whole>

Prints each finding as `path:line: message`, then a one-line summary; exits 1 on any finding.
Run from anywhere inside the repository (scripts/test.sh runs it).
"""
import ast
import glob
import os
import re
import sys

THRESHOLD = 80
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXCUSE = re.compile(r"^\s*#\s*long-function:\s*\S")


def functions(tree):
    """Every function and method of a module, nested ones included."""
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node


def excused(lines, node):
    """Whether the line before the function (its first decorator, if any) gives a reason."""
    first = min([node.lineno] + [d.lineno for d in node.decorator_list])
    return first >= 2 and bool(EXCUSE.match(lines[first - 2]))


def check_file(path):
    with open(path, encoding="utf-8") as f:
        text = f.read()
    lines = text.splitlines()
    rel = os.path.relpath(path, ROOT)
    findings = []
    for node in functions(ast.parse(text, filename=path)):
        length = node.end_lineno - node.lineno + 1
        if length > THRESHOLD and not excused(lines, node):
            findings.append(f"{rel}:{node.lineno}: {node.name} is {length} lines (over "
                            f"{THRESHOLD}): split it, or say why above it with "
                            f"'# long-function: <reason>'")
    return findings


def main():
    paths = sorted(glob.glob(os.path.join(ROOT, "addon", "**", "*.py"), recursive=True))
    findings = []
    for path in paths:
        findings.extend(check_file(path))
    for message in findings:
        print(message)
    print(f"check_python_size: {len(paths)} files, {len(findings)} functions over "
          f"{THRESHOLD} lines")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
