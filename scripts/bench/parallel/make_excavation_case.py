#!/usr/bin/python3
"""The cost of sharing the blocks out again within a run (docs/performance.md, "Blocks changing
owner"): scripts/bench/parallel/rock_mass_10k.toml with a circular opening of radius R on the
right-hand side, excavated after 100 steps, then STEPS steps. Removing the opening's block takes
its zones from the processes that held it: under mpirun the load is then out of balance, and
`--imbalance-limit` decides whether the blocks are shared out again.

Usage: /usr/bin/python3 scripts/bench/parallel/make_excavation_case.py OUT.toml [R_m [STEPS]]
"""
import os
import re
import sys

if not 2 <= len(sys.argv) <= 4:
    sys.exit(__doc__.strip())
radius = float(sys.argv[2]) if len(sys.argv) > 2 else 14.0
steps = int(sys.argv[3]) if len(sys.argv) > 3 else 400
here = os.path.dirname(os.path.abspath(__file__))
s = open(os.path.join(here, "rock_mass_10k.toml")).read()
opening = ('[[rock_mass.openings]]\nname = "opening"\nshape = "circle"\ncentre = ["%g m", "0 m"]\n'
           'radius = "%g m"\nsegments = 48\n\n' % (31.0 - radius - 2.0, radius))
s = s.replace("[in_situ]", opening + "[in_situ]", 1)
stages = ('[[stages]]\nname = "before"\nuntil = "steps"\nsteps = 100\n\n'
          '[[stages]]\nname = "excavate"\nexcavate = ["opening"]\nrelax_steps = 100\nuntil = "steps"\nsteps = %d\n\n' % steps)
s, n = re.subn(r'(?ms)^\[\[stages\]\]\nname = "step"\n.*?(?=^\[)', stages, s)
if n != 1:
    sys.exit("make_excavation_case.py: the [[stages]] table of rock_mass_10k.toml was not found")
s = s.replace('title = "Parallel benchmark: 10k deformable blocks"',
              'title = "Parallel benchmark: 10k deformable blocks, an opening excavated"', 1)
open(sys.argv[1], "w").write(s)
