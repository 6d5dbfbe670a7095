#!/usr/bin/env python3
"""Check tracked sources, READMEs, docs/*.md and bench/results/*.md for three kinds of stale text.

1. Session or issue numbers ("session N", "session-N", "issue N.M", "issues N and M", also
   split over a line break): they point at a planning history the reader does not have; a
   comment should say what and why.
2. Repository paths (native/..., tests/..., scripts/... ending in a file suffix) that do not
   exist: a citation of a moved or deleted file sends the reader nowhere. Not checked in
   bench/results/*.md, which record measurements at a named commit and may cite a file as it
   was then.
3. Commit hashes (7 to 12 lowercase hex digits, letters and digits both): history, not what
   the code does. Also allowed in bench/results/*.md only.

Prints each finding as `path:line: message`, then a one-line summary; exits 1 on any finding.
Run from anywhere inside the repository (scripts/test.sh runs it first).
"""
import os
import re
import subprocess
import sys

SUFFIXES = (".cpp", ".h", ".hpp", ".py", ".pyi", ".sh", ".cmake")
SHELL_SHEBANG = re.compile(r"^#!.*\b(ba|z|da)?sh\b")

NUMBER_PATTERNS = [
    (re.compile(r"\bsessions?\s+\d+", re.IGNORECASE), "session number"),
    (re.compile(r"\bsession-\d+", re.IGNORECASE), "session number"),
    (re.compile(r"\bissues?\s+#?\d+(\.\d+)?", re.IGNORECASE), "issue number"),
    (re.compile(r"\bissue-\d+", re.IGNORECASE), "issue number"),
]

# A short commit hash: a hex word with both a digit and a letter, not part of a longer word, a
# 0x literal or a #colour.
HASH_CANDIDATE = re.compile(r"(?<![\w#])[0-9a-f]{7,12}(?!\w)")


def commit_hashes(line):
    for m in HASH_CANDIDATE.finditer(line):
        word = m.group(0)
        if re.search(r"[0-9]", word) and re.search(r"[a-f]", word):
            yield word


PATH_PREFIXES = ("native", "addon", "tests", "bench", "scripts", "docs", "example_blends", "fuzz")
# A candidate starts at a prefix not glued to a longer path and runs to a space, a quote, a
# bracket, a comma or a semicolon; trailing full stops and colons are stripped afterwards.
PATH_CANDIDATE = re.compile(
    r"(?<![\w./-])(?:" + "|".join(PATH_PREFIXES) + r")/[^\s`'\"()\[\],;]*")
PATH_SUFFIX = re.compile(r"\.(py|cpp|h|md|sh|blend|txt|npz|npy|png|json|toml)$")
PLACEHOLDER_MARKS = ("*", "{", "<", "N.")
# Capitalised words the tree uses for a part of a path to fill in: bench/tradeoff/refs/SCENE_...
PLACEHOLDER_WORDS = re.compile(r"(?<![A-Za-z])(SCENE|NAME|PRESET)(?![A-Za-z])")
# A number word at a line's end whose number opens the next line (after comment marks).
NUMBER_WORD_AT_END = re.compile(r"\b(sessions?|issues?)\s*$", re.IGNORECASE)
NUMBER_AT_START = re.compile(r"^\s*(//+|#+|\*+|\"\"\")?\s*#?\d")


def repo_root():
    out = subprocess.run(["git", "rev-parse", "--show-toplevel"], capture_output=True,
                         text=True, check=True, cwd=os.path.dirname(os.path.abspath(__file__)))
    return out.stdout.strip()


def is_result_page(path):
    """bench/results/*.md: checked for numbers only (their paths are as of the commit measured)."""
    return (path.startswith("bench/results/") and path.count("/") == 2
            and path.endswith(".md"))


def is_excluded(path):
    parts = path.split("/")
    if is_result_page(path):
        return False
    # bench/results' data files and fuzz seeds are recorded output, not prose.
    if path.startswith("bench/results/") or path.startswith("fuzz/seeds/"):
        return True
    # This checker's own test holds examples of what it finds.
    if path == "tests/python/test_check_comments.py":
        return True
    # Test data (tests/**/data) holds recorded inputs and references, not prose.
    return parts[0] == "tests" and "data" in parts[1:-1]


def is_shell_script(root, path):
    try:
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
            return bool(SHELL_SHEBANG.match(f.readline()))
    except OSError:
        return False


def files_to_scan(root):
    out = subprocess.run(["git", "ls-files", "-z"], capture_output=True, text=True,
                         check=True, cwd=root)
    picked = []
    for path in out.stdout.split("\0"):
        # A tracked file deleted in the work tree has nothing to check.
        if not path or is_excluded(path) or not os.path.isfile(os.path.join(root, path)):
            continue
        name = os.path.basename(path)
        # Every README (the top one and those of add-on, bench and example folders), docs/*.md
        # and bench/results/*.md.
        if (path.endswith(SUFFIXES) or name in ("CMakeLists.txt", "README.md")
                or (path.startswith("docs/") and path.count("/") == 1 and name.endswith(".md"))
                or is_result_page(path)):
            picked.append(path)
        elif "." not in name and is_shell_script(root, path):
            # Extensionless shell scripts such as .ci/run.
            picked.append(path)
    return sorted(picked)


def cited_paths(line):
    """The repository paths a line cites, placeholders and globs left out."""
    for m in PATH_CANDIDATE.finditer(line):
        token = m.group(0).rstrip(".:")
        if any(mark in token for mark in PLACEHOLDER_MARKS) or PLACEHOLDER_WORDS.search(token):
            continue
        token = token.split("::", 1)[0]  # a pytest node id: path::test_name
        token = re.sub(r":\d.*$", "", token)  # file:line
        if PATH_SUFFIX.search(token):
            yield token


def check_file(root, path):
    findings = []
    with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
        lines = f.read().splitlines()
    # CMake names sources relative to the directory of the list file that names them.
    bases = [root]
    if os.path.basename(path) == "CMakeLists.txt" or path.endswith(".cmake"):
        bases.append(os.path.join(root, os.path.dirname(path)))
    for number, line in enumerate(lines, 1):
        for pattern, what in NUMBER_PATTERNS:
            for m in pattern.finditer(line):
                findings.append(("number", f"{path}:{number}: {what}: '{m.group(0)}'"))
        end = NUMBER_WORD_AT_END.search(line)
        if end and number < len(lines) and NUMBER_AT_START.match(lines[number]):
            what = end.group(1).lower().rstrip("s")
            findings.append(("number", f"{path}:{number}: {what} number across the line break: "
                                       f"'{end.group(1)}' + '{lines[number].strip()[:20]}'"))
        if is_result_page(path):
            continue
        for word in commit_hashes(line):
            findings.append(("hash", f"{path}:{number}: commit hash: '{word}'"))
        for cited in cited_paths(line):
            if not any(os.path.exists(os.path.join(base, cited)) for base in bases):
                findings.append(("path", f"{path}:{number}: cites a missing path: {cited}"))
    return findings


def main():
    root = repo_root()
    files = files_to_scan(root)
    findings = []
    for path in files:
        findings.extend(check_file(root, path))
    for _, message in findings:
        print(message)
    numbers = sum(1 for kind, _ in findings if kind == "number")
    hashes = sum(1 for kind, _ in findings if kind == "hash")
    paths = len(findings) - numbers - hashes
    print(f"check_comments: {len(files)} files, {numbers} session/issue numbers, "
          f"{hashes} commit hashes, {paths} missing paths")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
