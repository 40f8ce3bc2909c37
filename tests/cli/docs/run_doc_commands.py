"""Runs the command blocks of rockdem's documentation pages as a reader would type them.

Usage: /usr/bin/python3 run_doc_commands.py WORKDIR TUTORIAL_BINARY PAGE.md...

WORKDIR is a folder laid out like a clone after `scripts/demo`'s build: build/rockdem, scripts/,
cases/ (tests/cli/docs_commands.sh makes it). Every ```sh block runs there with bash -e, every
```python block with /usr/bin/python3; each must exit 0, and every file or folder a command names
as an output (--out, --json, --plot, --save-model, --report, --write-blocks, -o, > FILE) must exist
afterwards. A few commands are not run here, each for a stated reason (printed); `scripts/build`
(after the tutorial adds an effect) is mirrored by switching build/rockdem to TUTORIAL_BINARY,
rockdem built with the effect exactly as the page lists it.
"""
import os
import re
import shlex
import subprocess
import sys
import textwrap

NOT_RUN = {
    "scripts/demo": "the README's first command: the stop check runs it from a fresh clone",
    "scripts/test": "the README's second command: CI runs it (it would run this test again)",
}
# Commands run in a smaller form: (the form, what it must write, why).
SMALLER = {
    "scripts/run-lab-dem": ("scripts/run-lab-dem cases/direct_shear/test08_mohr_coulomb.toml -- --stages 1 "
                            "--shear-velocity '1000 mm/s'", "lab-dem/test08_mohr_coulomb/test08.csv",
                            "one case, one test stage, at 1000 mm/s: the 21 cases take about 20 minutes"),
}
OUTPUT_OPTIONS = {"--out", "--json", "--plot", "--save-model", "--report", "--write-blocks", "-o"}


def blocks(page):
    """(language, first line number, text) of every fenced block; indented fences included."""
    lines = open(page, encoding="utf-8").read().split("\n")
    out, i = [], 0
    while i < len(lines):
        m = re.match(r"^(\s*)```(\w*)\s*$", lines[i])
        if not m:
            i += 1
            continue
        indent, lang, start = m.group(1), m.group(2), i + 1
        body = []
        i += 1
        while i < len(lines) and lines[i].strip() != "```":
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
            i += 1
        out.append((lang, start, textwrap.dedent("\n".join(body))))
        i += 1
    return out


def commands(text):
    """The block's commands, continuation lines joined, comments and blank lines dropped."""
    joined = text.replace("\\\n", " ")
    return [ln for ln in joined.split("\n") if ln.strip() and not ln.strip().startswith("#")]


def named_outputs(cmd):
    """Paths a command names as outputs (its option values and redirections)."""
    try:
        words = shlex.split(cmd, comments=True)
    except ValueError:
        return []
    paths = []
    for k, w in enumerate(words[:-1]):
        if w in OUTPUT_OPTIONS or w == ">":
            paths.append(words[k + 1])
    return [p for p in paths if "$" not in p]


def main():
    work, tutorial_bin, pages = sys.argv[1], sys.argv[2], sys.argv[3:]
    env = dict(os.environ)
    failed = 0
    for page in pages:
        for lang, line, text in blocks(page):
            where = f"{os.path.basename(page)}:{line}"
            if lang == "python":
                run = subprocess.run(["/usr/bin/python3", "-c", text], cwd=work, env=env, capture_output=True, text=True,
                                     timeout=600)
                if run.returncode != 0:
                    print(f"FAIL {where} python block: exit {run.returncode}: {run.stderr.strip()[-400:]}")
                    failed = 1
                else:
                    print(f"ok   {where} python block ({len(text.splitlines())} lines)")
                continue
            if lang != "sh":
                continue
            script, outputs = [], []
            for cmd in commands(text):
                first = cmd.split()[0]
                if first in NOT_RUN:
                    print(f"     {where} not run here: {cmd.strip()} ({NOT_RUN[first]})")
                    continue
                if first in SMALLER and shlex.split(cmd, comments=True) == [first]:
                    form, wrote, why = SMALLER[first]
                    print(f"     {where} run smaller: {form} ({why})")
                    script.append(form)
                    outputs.append(wrote)
                    continue
                if first == "scripts/build":
                    # rockdem rebuilt with the page's new effect: the binary built from its listing.
                    script.append(f"ln -sfn {shlex.quote(tutorial_bin)} build/rockdem")
                    continue
                script.append(cmd)
                outputs += named_outputs(cmd)
            if not script:
                continue
            run = subprocess.run(["bash", "-e", "-c", "\n".join(script)], cwd=work, env=env, capture_output=True, text=True,
                                 timeout=900)
            missing = [p for p in outputs if not os.path.exists(os.path.join(work, p))]
            if run.returncode != 0:
                print(f"FAIL {where}: exit {run.returncode}: {(run.stderr or run.stdout).strip()[-600:]}")
                failed = 1
            elif missing:
                print(f"FAIL {where}: the block ran but did not write {', '.join(missing)}")
                failed = 1
            else:
                shown = "; ".join(c.strip()[:70] for c in script)
                print(f"ok   {where}: {shown}" + (f" (wrote {', '.join(outputs)})" if outputs else ""))
    return failed


if __name__ == "__main__":
    sys.exit(main())
