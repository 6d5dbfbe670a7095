"""The comment checker (scripts/check_comments.py) finds what it is meant to and nothing else."""
import importlib.util
import os

HERE = os.path.dirname(os.path.abspath(__file__))
SPEC = importlib.util.spec_from_file_location(
    "check_comments", os.path.join(HERE, "..", "..", "scripts", "check_comments.py"))
cc = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(cc)


def test_commit_hashes_are_found():
    assert list(cc.commit_hashes("// fixed at f53c3ab, see")) == ["f53c3ab"]
    assert list(cc.commit_hashes("(dbda0eb: rRMSE 0.025)")) == ["dbda0eb"]
    assert list(cc.commit_hashes("between 65b757e and b224d4f0")) == ["65b757e", "b224d4f0"]


def test_words_numbers_and_literals_are_not_hashes():
    for line in ("Hierarchy::mix(pt.seed, 0x5ea1edu)", "colour #a1b2c3d4", "a deadbeef value",
                 "1234567 rays", "sha256 " + "ab12" * 16, "the facade of cafebabe1x",
                 "version 1e-9", "Decade"):
        assert list(cc.commit_hashes(line)) == [], line


def test_session_and_issue_numbers_are_found():
    def numbers(line):
        return [m.group(0) for p, _ in cc.NUMBER_PATTERNS for m in p.finditer(line)]
    assert numbers("as measured in session 12") == ["session 12"]
    assert numbers("see issue #35.2") == ["issue #35.2"]
    assert numbers("a session object, an issue with the light") == []
