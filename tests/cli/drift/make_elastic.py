# make_elastic.py SMALL.toml OUT.toml [--quiet-only] [--glued] (tests/cli/drift_no_shaking.sh):
# the small drift study with every joint linear_elastic; the excavation taken to a ratio of 1e-11
# (a tighter equilibrium than the study's 1e-5, so that "no motion" can be told from the
# equilibrium's own residual); a stage with the events' boundaries and damping but no input, as
# long as an event, before the two events; and the energy terms recorded. --quiet-only: the run
# ends after that stage (no events, and no [drift] table: the check reads the histories and
# checkpoints). --glued: every joint keeps coulomb_slip with 1 GPa of cohesion and of tension
# instead (an elastic joint that neither slips nor opens: the rock mass as an elastic continuum
# with compliant joints), the stages as in the study (docs/drift-study.md, "Not done yet").
import re, sys
src, dst = sys.argv[1:3]
quiet_only = "--quiet-only" in sys.argv[3:]
glued = "--glued" in sys.argv[3:]
s = open(src).read()
s = s.replace('"../data/ground_motions', '"' + src.rsplit("/", 2)[0] + '/data/ground_motions')
# Every joint entry: the elastic law with its stiffnesses (strength keys dropped).
def elastic(m):
    body = m.group(0)
    body = re.sub(r'(?m)^law = .*$', 'law = "linear_elastic"', body)
    body = re.sub(r'(?m)^(friction|cohesion|tension) = .*\n', '', body)
    return body
def glue(m):
    body = re.sub(r'(?m)^(cohesion|tension) = .*\n', '', m.group(0))
    return re.sub(r'(?m)^(friction = .*\n)', r'\1cohesion = "1 GPa"\ntension = "1 GPa"\n', body)
if glued:
    s = re.sub(r'(?ms)^\[\[joints\]\].*?(?=^\[)', glue, s)
    for t in ("kinetic", "strain", "contact", "gravity_work", "boundary_work", "slip", "damping", "imbalance"):
        s += f'\n[[histories]]\nname = "energy_{t}"\nquantity = "energy"\ncomponent = "{t}"\n'
    open(dst, "w").write(s)
    sys.exit(0)
s = re.sub(r'(?ms)^\[\[joints\]\].*?(?=^\[)', elastic, s)
# The quiet stage: event_1's settings without its motion, two seconds (the event's length).
m = re.search(r'(?ms)^\[\[stages\]\]\nname = "event_1"\n.*?(?=^\[)', s)
event = m.group(0)
quiet = event.replace('name = "event_1"', 'name = "quiet"')
quiet = quiet.replace('motion = "elcentro"\npgv = "0.5 m/s"\nduration = "auto"', 'duration = "2 s"')
assert quiet != event.replace('name = "event_1"', 'name = "quiet"')
s = s.replace(event, quiet + event)
s = s.replace('stages = ["event_1", "event_2"]', 'stages = ["quiet", "event_1", "event_2"]')
m = re.search(r'(?ms)^\[\[stages\]\]\nname = "excavate"\n.*?(?=^\[)', s)
excavate = m.group(0)
tight = excavate.replace("ratio = 1e-5", "ratio = 1e-11").replace("max_steps = 100000", "max_steps = 150000")
assert tight != excavate
s = s.replace(excavate, tight)
for t in ("kinetic", "strain", "contact", "gravity_work", "boundary_work", "slip", "damping", "imbalance"):
    s += f'\n[[histories]]\nname = "energy_{t}"\nquantity = "energy"\ncomponent = "{t}"\n'
s = s.replace("history_interval = 200", "history_interval = 100")
if quiet_only:
    for name in ("event_1", "rest_1", "event_2", "rest_2"):
        m = re.search(r'(?ms)^\[\[stages\]\]\nname = "%s"\n.*?(?=^\[)' % name, s)
        s = s.replace(m.group(0), "")
    s = s.replace('stages = ["in_situ", "excavate", "rest_1", "rest_2"]', 'stages = ["in_situ", "excavate"]')
    s = s.replace('stages = ["quiet", "event_1", "event_2"]', 'stages = ["quiet"]')
    s = re.sub(r'(?ms)^\[drift\].*?(?=^\[|\Z)', "", s)
    s = re.sub(r'(?ms)^\[\[motions\]\].*?(?=^\[)', "", s)
open(dst, "w").write(s)
