"""Shared by the Python parts of the command-line tests (imported with PYTHONPATH=tests/cli/lib;
not a test itself): each check prints one line, `ok   <what>` or `FAIL <what>`, and done() exits 1
when any failed, so that the shell script's `|| fail=1` sees it."""
import csv
import sys

failed = False


def check(good, what):
    """Report one check; a failed one makes done() exit 1."""
    global failed
    print(("ok   " if good else "FAIL ") + what)
    failed = failed or not good


def rows(path):
    """The rows of a CSV file whose `#` lines are comments (rockdem's drift/*.csv)."""
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def done():
    sys.exit(1 if failed else 0)
