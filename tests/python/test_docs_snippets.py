"""Every code block of README.md and docs/*.md runs as written (issue 24, a new user's item 1).

A new user pastes the blocks: the shell blocks of a page into one shell, in order (the service's
session needs the server the first block starts), each Python block into a script of its own (the
Dask example must work pasted alone), each job document (a JSON block with "brdfbake_job") into
`brdfbake run`. They run in a temporary folder laid out like the repository's root (examples/ and
../shared beside it), with the built tool on PATH and the installed package, each page bounded in
time.

Blocks that are not meant to run say so in the Markdown itself, never by a rule of this file:
- a ```text fence: output, a synopsis, a diagram;
- an HTML comment on the line before the fence, `<!-- snippet: not run: WHY -->` (a benchmark that
  needs a quiet machine, a cluster, the installation this suite already performs);
- `<!-- snippet: run with "A" as "B", "C" as "D": WHY -->`: the block runs with A replaced by B, a
  smaller variant labelled as such in the page (the MERL batches that write gigabytes as written).
A block in any other language without such a comment fails the test: nothing is skipped silently.

This is a pytest test rather than a ctest one because half the blocks are Python that import the
installed package, which only the Python suite's environment (scripts/test.sh: `pip install .`)
has; the shell blocks use the tool that suite is given ($BRDFBAKE_CLI).
"""

import json
import os
import re
import subprocess
import sys
import time

import pytest

from conftest import REPO

PAGES = ["README.md"] + sorted(str(p.relative_to(REPO)) for p in (REPO / "docs").glob("*.md"))
RUN_LANGUAGES = {"sh", "python", "json"}
MARKER = re.compile(r"^<!--\s*snippet:\s*(.*?)\s*-->\s*$")
PAGE_SECONDS = 420  # a page's blocks together; the slowest page (docs/VIEW.md's real bake) takes ~60 s alone


def blocks(page):
    """The page's fenced blocks: (line, language, text, marker or None)."""
    lines = (REPO / page).read_text().split("\n")
    out, k = [], 0
    while k < len(lines):
        m = re.match(r"^\s*```(\S*)\s*$", lines[k])
        if not m:
            k += 1
            continue
        end = k + 1
        while end < len(lines) and not lines[end].strip().startswith("```"):
            end += 1
        before = MARKER.match(lines[k - 1].strip()) if k > 0 else None
        out.append((k + 1, m.group(1), "\n".join(lines[k + 1:end]) + "\n", before.group(1) if before else None))
        k = end + 1
    return out


def plan(page):
    """(what runs, what is not run with why, what is wrong with the page's marking)."""
    run, not_run, wrong = [], [], []
    for line, language, text, marker in blocks(page):
        where = f"{page}:{line}"
        if language == "text":
            not_run.append((where, "a ```text block"))
            continue
        if marker and marker.startswith("not run:"):
            not_run.append((where, marker))
            continue
        if language not in RUN_LANGUAGES:
            wrong.append(f"{where}: a ```{language or ''} block neither run nor marked (```text, or "
                         "<!-- snippet: not run: WHY --> on the line before)")
            continue
        if language == "json" and '"brdfbake_job"' not in text:
            wrong.append(f"{where}: a JSON block that is not a job document: mark it ```text or not run")
            continue
        if marker:
            m = re.match(r"^run with (.*?):\s*\S", marker)
            if not m:
                wrong.append(f"{where}: unknown snippet marker '{marker}'")
                continue
            for old, new in re.findall(r'"((?:[^"\\]|\\.)*)" as "((?:[^"\\]|\\.)*)"', m.group(1)):
                if old not in text:
                    wrong.append(f"{where}: the marker replaces '{old}', which the block does not hold")
                text = text.replace(old, new)
        run.append((where, language, text))
    return run, not_run, wrong


def test_every_block_is_run_or_marked():
    wrong = [w for page in PAGES for w in plan(page)[2]]
    assert not wrong, "\n".join(wrong)


def workspace(tmp_path, shared):
    """A folder laid out as the repository's root is for the docs: examples/, ../shared."""
    root = tmp_path / "work"
    root.mkdir()
    (root / "examples").symlink_to(REPO / "examples")
    (tmp_path / "shared").symlink_to(shared)
    return root


@pytest.mark.parametrize("page", PAGES)
def test_page_blocks_run_as_written(page, tmp_path, cli, shared_dir):
    run, not_run, wrong = plan(page)
    assert not wrong, "\n".join(wrong)
    if not run:
        return  # every block is marked (checked above): nothing to run
    text = "".join(t for _, _, t in run)
    if "../shared" in text and shared_dir is None:
        pytest.skip(f"{page} uses the shared maps and scenes (../shared), which are absent")
    root = workspace(tmp_path, shared_dir or tmp_path / "no-shared")
    env = dict(os.environ)
    env["PATH"] = os.path.dirname(os.path.abspath(cli)) + os.pathsep + os.path.dirname(sys.executable) + \
        os.pathsep + env.get("PATH", "")
    env["PYTHONUNBUFFERED"] = "1"
    deadline_left = PAGE_SECONDS

    def go(argv, where, stdin=None):
        nonlocal deadline_left
        start = time.monotonic()
        try:
            got = subprocess.run(argv, cwd=root, env=env, input=stdin, capture_output=True, text=True,
                                 timeout=max(deadline_left, 1), start_new_session=True)
        except subprocess.TimeoutExpired as e:
            pytest.fail(f"{where}: still running after the page's {PAGE_SECONDS} s\n{e.stderr or ''}"[-4000:])
        deadline_left -= time.monotonic() - start
        assert got.returncode == 0, f"{where}: exit {got.returncode}\n{got.stdout[-2000:]}\n{got.stderr[-4000:]}"

    # The shell blocks in one shell, in order; a server they started in the background is stopped.
    shell = [(w, t) for w, lang, t in run if lang == "sh"]
    if shell:
        script = "set -e -o pipefail\ntrap 'kill $(jobs -p) 2>/dev/null || true' EXIT\n"
        for where, t in shell:
            script += f"echo '### {where}' >&2\n{t}"
        go(["bash", "-c", script], f"{page} (shell blocks {', '.join(w for w, _ in shell)})")
    for k, (where, language, t) in enumerate(run):
        if language == "python":
            path = root / f"snippet_{k}.py"
            path.write_text(t)
            go([sys.executable, str(path)], where)
        elif language == "json":
            path = root / f"job_{k}.json"
            path.write_text(t)
            json.loads(t)
            go([cli, "run", str(path), "-o", str(root / f"job_{k}_out"), "--quiet"], where)
