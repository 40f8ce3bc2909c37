#!/usr/bin/python3
"""The drift study's cost per second of shaking (docs/performance.md, "The drift study on 1 and 2
processes"): cases/drift/small.toml with its first earthquake cut to 0.5 s and the stages after it
reduced to a step each, so that a run restarted from the excavation's checkpoint is 0.5 s of
shaking (25,000 steps) and the results written after it.

Usage: /usr/bin/python3 scripts/bench/drift_event/make_case.py OUT.toml
"""
import os
import re
import sys

if len(sys.argv) != 2:
    sys.exit(__doc__.strip())
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
s = open(os.path.join(root, "cases", "drift", "small.toml")).read()
s = s.replace('"../data/', '"' + os.path.join(os.path.abspath(root), "cases", "data") + "/")


def stage(name):
    return re.search(r'(?ms)^\[\[stages\]\]\nname = "%s"\n.*?(?=^\[)' % name, s).group(0)


event = stage("event_1")
s = s.replace(event, event.replace('duration = "auto"', 'duration = "0.5 s"'))
for rest in ("rest_1", "rest_2"):
    s = s.replace(stage(rest), '[[stages]]\nname = "%s"\nuntil = "steps"\nsteps = 1\n\n' % rest)
event = stage("event_2")
s = s.replace(event, event.replace('duration = "auto"', 'duration = "0.0002 s"'))
open(sys.argv[1], "w").write(s)
