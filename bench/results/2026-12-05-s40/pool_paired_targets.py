# Pools the two / one figures of this session's paired_targets*.txt runs (all on the code that
# lands; run 3 has no round-trip readings: host_scaling was missing beside its BIN).
#   python3 pool_paired_targets.py paired_targets.txt paired_targets_2.txt ...
import re, statistics as st, sys
vals = {'12000': [], '1e5': []}
for f in sys.argv[1:]:
    for l in open(f):
        for key in vals:
            m = re.search(r'two/one ' + key + r' ([\d.]+) \([\d.\-]+\)(?: \[(\d+)/(\d+)\])?', l)
            if m:
                a, b = (int(m.group(2)), int(m.group(3))) if m.group(2) else (None, None)
                vals[key].append((float(m.group(1)), a, b, f))
print("two / one in turns, pooled over " + ", ".join(sys.argv[1:]))
for key, v in vals.items():
    f = lambda s: f"{st.median(s):.3f} ({len(s)})" if s else "- (0)"
    allv = [x for x, *_ in v]
    near = [x for x, a, b, _ in v if a is not None and a < 250 and b < 250]
    far = [x for x, a, b, _ in v if a is not None and a >= 250 and b >= 250]
    ch = [x for x, a, b, _ in v if a is not None and (a < 250) != (b < 250)]
    unread = [x for x, a, *_ in v if a is None]
    print(f"{key}: all {f(allv)}, near {f(near)}, far {f(far)}, changed {f(ch)}, not read {f(unread)}")
    for name in sys.argv[1:]:
        run = [x for x, *_, g in v if g == name]
        print(f"  {name}: {f(run)}")
