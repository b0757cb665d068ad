"""The commit form of docs/architecture.md ("Contributor notes: commits"), checked on the commits
made since the rule was written (the commit that added this file, and every one after it): a
subject of at most 72 characters, and a blank line between it and any body."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from app import PROJECT_ROOT

SUBJECT_MAX = 72


def _git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=PROJECT_ROOT, capture_output=True, text=True,
                          check=True).stdout


def _since_the_rule() -> list[tuple[str, str]]:
    """(hash, whole message) of the commits from the one that added this file to HEAD."""
    added = _git("log", "--diff-filter=A", "--format=%H", "--", "tests/unit/test_commits.py")
    if not added.split():  # not committed yet: the commits to come are checked once it is
        return []
    first = added.split()[-1]
    hashes = [first, *_git("rev-list", "--reverse", f"{first}..HEAD").split()]
    return [(h, _git("log", "-1", "--format=%B", h)) for h in hashes]


def problems(message: str) -> list[str]:
    """What a commit message breaks of the form (empty: nothing)."""
    lines = message.rstrip("\n").split("\n")
    subject = lines[0]
    out = []
    if not subject.strip() or len(subject) > SUBJECT_MAX:
        out.append(f"subject of {len(subject)} characters: {subject[:80]!r}")
    if len(lines) > 1 and lines[1].strip():
        out.append("no blank line between the subject and the body")
    return out


def _git_checkout() -> bool:
    if shutil.which("git") is None:
        return False
    try:
        return _git("rev-parse", "--is-inside-work-tree").strip() == "true" and \
            _git("rev-parse", "--is-shallow-repository").strip() == "false"
    except subprocess.CalledProcessError:
        return False


@pytest.mark.skipif(not _git_checkout(),
                    reason="not a full git checkout (no git, or a shallow clone): no history")
def test_commit_subjects_since_the_rule_fit_72_characters_and_stand_alone():
    bad = [f"{h[:7]}: {p}" for h, message in _since_the_rule() for p in problems(message)]
    assert bad == [], "\n".join(bad)


def test_the_check_refuses_a_long_subject_and_a_glued_body():
    """The rule itself, on made-up messages (what the test above applies to the history)."""
    assert problems("Draw the sky last\n\nWhy, and the figures.\n") == []
    assert problems("x" * 72) == []
    assert len(problems("x" * 73)) == 1
    assert problems("Subject\nbody glued to it") == ["no blank line between the subject and the "
                                                     "body"]
    assert len(problems("")) == 1
