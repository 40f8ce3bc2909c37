"""Replay of a seeded mutation corpus through rockdem's parsers (tests/cli/fuzz_replay.sh).

usage: /usr/bin/python3 tests/fuzz/replay.py ROCKDEM SOURCE_DIR [--per-target N] [--first K]
                                            [--write-input TARGET INDEX FILE]

Each target is one parser reached through the command a user runs, with a seed input kept in
tests/fuzz/seeds/ (copies of small inputs of the repository, so that the corpus does not change
when a case is edited):

  dem_case      `rockdem run CASE --write-blocks DIR` (case reader, model building, rock-mass
                generator, mesher) on stack_dem.toml and rock_mass_dem.toml
  lab_case      `rockdem run LAB_CASE --write-case FILE` (laboratory-test case reader) on
                lab_test09.toml
  element_case  `rockdem element CASE --out FILE.csv` (element driver's case reader and run) on
                element_fig3-2.toml
  measurement   `rockdem compare --data FILE --model FILE` (measurement CSV reader) on measured.csv
  accelerogram  `rockdem ground-motion FILE --units g --column 2` (record reader) on
                accelerogram.csv
  calibration   `rockdem run CASE --write-blocks DIR` on a case whose joint names a calibrate JSON
                (calibration_case.toml + calibration.json, the JSON mutated)

Mutation i of a target is drawn by a random generator seeded with (target, i): the same inputs
on every machine and every run, so a failure is reproduced with --write-input. The oracle: the
command ends within the time limit, without a signal, with exit 0 or 2 (1 only where a file
cannot be written, which does not happen here); an exit 2 prints a message that names the input
file. Prints a line per failure and a summary; exit 1 if any failed.
"""
import argparse
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

EXTREMES = ["0", "-1", "-0", "1e308", "-1e308", "1e-300", "nan", "inf", "-inf", "2147483648",
            "9223372036854775808", "", "0x10", "1e", "--1", "abc", "1,5", "3.4.5", "1e-5", "1e9"]
UNITS = ["mm", "km", "MPa", "GPa", "kPa", "deg", "rad", "s", "ms", "m/s", "g", "kg/m3", "GPa/m", "",
         "furlong", "m/s2", "1/s", "Pa*s"]
VALUES = ['[1, 2]', 'true', '{ a = 1 }', '"x"', '1', '""', '[]', '"1e308 m"', '"-5 MPa"', '[["a"]]',
          '"0 mm"', '"nan mm"', '2026-11-26']
JUNK = ["[", "]", "[[", "]]", "=", "\"", "'", "{", "}", ",", "#", "\\", "\u00e9", "\u2212", "\t", "\x00", ";"]
NUMBER = re.compile(r"(?<![A-Za-z_])[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")
QUANTITY_UNIT = re.compile(r"(\"[-+]?[\d.eE+-]+\s*)([A-Za-z/0-9*]+)(\")")
KEY = re.compile(r"^(\s*)([A-Za-z_][A-Za-z_0-9]*)(\s*=)", re.M)


def mutate_once(text, rng):
    """One mutation of `text`, and its description."""
    lines = text.split("\n")
    op = rng.randrange(11)
    if op == 0:
        spans = [m.span() for m in NUMBER.finditer(text)]
        if spans:
            a, b = rng.choice(spans)
            v = rng.choice(EXTREMES)
            return text[:a] + v + text[b:], f"number '{text[a:b]}' -> '{v}'"
    if op == 1:
        ms = list(QUANTITY_UNIT.finditer(text))
        if ms:
            m = rng.choice(ms)
            u = rng.choice(UNITS)
            return text[:m.start(2)] + u + text[m.end(2):], f"unit '{m.group(2)}' -> '{u}'"
    if op == 2 and len(lines) > 1:
        i = rng.randrange(len(lines))
        return "\n".join(lines[:i] + lines[i + 1:]), f"line {i + 1} deleted"
    if op == 3 and lines:
        i = rng.randrange(len(lines))
        return "\n".join(lines[:i + 1] + [lines[i]] + lines[i + 1:]), f"line {i + 1} duplicated"
    if op == 4 and len(lines) > 2:
        i, j = rng.sample(range(len(lines)), 2)
        lines[i], lines[j] = lines[j], lines[i]
        return "\n".join(lines), f"lines {i + 1} and {j + 1} swapped"
    if op == 5 and text:
        k = rng.randrange(len(text))
        return text[:k], f"truncated at character {k}"
    if op == 6 and text:
        k = rng.randrange(len(text))
        c = chr(rng.choice([rng.randrange(32, 127), rng.randrange(0, 32), rng.randrange(0x80, 0x2FFF)]))
        return text[:k] + c + text[k + 1:], f"character {k} -> U+{ord(c):04X}"
    if op == 7 and text:
        k = rng.randrange(len(text))
        j = rng.choice(JUNK)
        return text[:k] + j + text[k:], f"'{j!r}' inserted at {k}"
    if op == 8:
        ms = list(KEY.finditer(text))
        if ms:
            m = rng.choice(ms)
            key = m.group(2)
            new = key[:-1] if len(key) > 1 and rng.random() < 0.5 else key + rng.choice("sx_")
            return text[:m.start(2)] + new + text[m.end(2):], f"key '{key}' -> '{new}'"
    if op == 9:
        ms = list(KEY.finditer(text))
        if ms:
            m = rng.choice(ms)
            end = text.find("\n", m.end())
            end = len(text) if end < 0 else end
            v = rng.choice(VALUES)
            return text[:m.end()] + " " + v + text[end:], f"value of '{m.group(2)}' -> {v}"
    if op == 10:
        return "", "emptied"
    # The chosen operation did not apply (no numbers, one line, ...): a column or field swap.
    if "," in text:
        k = rng.choice([m.start() for m in re.finditer(",", text)])
        return text[:k] + ";" + text[k + 1:], f"comma at {k} -> ';'"
    return text + "\n=", "'=' appended"


def mutate(text, rng):
    """One to three mutations, described."""
    said = []
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        text, what = mutate_once(text, rng)
        said.append(what)
    return text, "; ".join(said)


def targets(src):
    seeds = os.path.join(src, "tests", "fuzz", "seeds")

    def seed(name):
        with open(os.path.join(seeds, name), encoding="utf-8") as f:
            return f.read()

    return [
        # name, seed text, the file name the mutated input gets, command builder (input path, work dir)
        ("dem_case", seed("stack_dem.toml"), "stack_dem.toml",
         lambda f, w: ["run", f, "--write-blocks", os.path.join(w, "blocks")]),
        ("dem_case", seed("rock_mass_dem.toml"), "rock_mass_dem.toml",
         lambda f, w: ["run", f, "--write-blocks", os.path.join(w, "blocks")]),
        ("lab_case", seed("lab_test09.toml"), "lab_test09.toml",
         lambda f, w: ["run", f, "--write-case", os.path.join(w, "dem.toml")]),
        ("element_case", seed("element_fig3-2.toml"), "element_fig3-2.toml",
         lambda f, w: ["element", f, "--out", os.path.join(w, "element.csv")]),
        ("measurement", seed("measured.csv"), "measured.csv",
         lambda f, w: ["compare", "--data", f, "--model", f, "--quiet"]),
        ("accelerogram", seed("accelerogram.csv"), "accelerogram.csv",
         lambda f, w: ["ground-motion", f, "--units", "g", "--column", "2"]),
        ("calibration", seed("calibration.json"), "calibration.json",
         lambda f, w: ["run", os.path.join(w, "calibration_case.toml"), "--write-blocks", os.path.join(w, "blocks")]),
    ]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("rockdem")
    ap.add_argument("src")
    ap.add_argument("--per-target", type=int, default=60, help="mutations per seed input (default 60)")
    ap.add_argument("--first", type=int, default=0, help="index of the first mutation (default 0)")
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds a command may take (default 60)")
    ap.add_argument("--write-input", nargs=3, metavar=("SEED_FILE", "INDEX", "OUT"),
                    help="write mutation INDEX of the seed file SEED_FILE (e.g. stack_dem.toml) to OUT and stop")
    a = ap.parse_args(argv)
    a.rockdem = os.path.abspath(a.rockdem)  # the commands run in their own folders
    all_targets = targets(a.src)
    if a.write_input:
        name, index, out = a.write_input
        for _, text, file_name, _ in all_targets:
            if file_name == name:
                mutated, what = mutate(text, random.Random(f"{file_name}:{int(index)}"))
                with open(out, "w", encoding="utf-8", errors="surrogateescape") as f:
                    f.write(mutated)
                print(f"{out}: mutation {index} of {name}: {what}")
                return 0
        sys.exit(f"replay.py: no seed '{name}'; seeds: {', '.join(t[2] for t in all_targets)}")

    tried, failures, codes = 0, [], {}
    t0 = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="rockdem_fuzz_") as tmp:
        for target, text, file_name, command in all_targets:
            for i in range(a.first, a.first + a.per_target):
                work = os.path.join(tmp, f"{target}_{i}")
                os.makedirs(work)
                mutated, what = mutate(text, random.Random(f"{file_name}:{i}"))
                path = os.path.join(work, file_name)
                with open(path, "w", encoding="utf-8", errors="surrogateescape") as f:
                    f.write(mutated)
                if target == "calibration":
                    shutil.copy(os.path.join(a.src, "tests", "fuzz", "seeds", "calibration_case.toml"), work)
                args = [a.rockdem] + command(path, work)
                tried += 1
                try:
                    r = subprocess.run(args, capture_output=True, timeout=a.timeout, cwd=work)
                    code, out = r.returncode, (r.stdout + r.stderr).decode("utf-8", "replace")
                except subprocess.TimeoutExpired:
                    code, out = "timeout", ""
                codes[code] = codes.get(code, 0) + 1
                problem = None
                if code == "timeout":
                    problem = f"no answer within {a.timeout:g} s"
                elif code < 0 or code >= 128:
                    problem = f"ended by a signal (exit {code})"
                elif code not in (0, 2):
                    problem = f"exit {code} (wanted 0, or 2 for bad input)"
                elif code == 2 and file_name not in out:
                    problem = "the message does not name the input file"
                if problem:
                    last = out.strip().splitlines()[-1] if out.strip() else "(no output)"
                    failures.append(f"{file_name} #{i} ({what}): {problem}: {last[:300]}")
                shutil.rmtree(work, ignore_errors=True)
    dt = time.monotonic() - t0
    for f in failures:
        print("FAIL " + f)
    summary = ", ".join(f"exit {k}: {v}" for k, v in sorted(codes.items(), key=lambda kv: str(kv[0])))
    print(f"{tried} mutated inputs through {len(all_targets)} seeds in {dt:.1f} s ({tried / dt:.1f} a second): "
          f"{summary}; {len(failures)} failed")
    if failures:
        print(f"reproduce one: /usr/bin/python3 tests/fuzz/replay.py {a.rockdem} {a.src} --write-input SEED INDEX FILE")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
