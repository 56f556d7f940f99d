import sys, statistics as st
lines=[l.split() for l in open(sys.argv[1])]
names=lines[0][3:]
rows=[l for l in lines[1:] if l and l[0].isdigit() and len(l)==3+len(names)]
def cls(r):
    a,b=float(r[1]),float(r[2])
    return 'near' if a<250 and b<250 else ('far' if a>=250 and b>=250 else 'changed')
for c in ('near','far','changed','all'):
    sel=[r for r in rows if c=='all' or cls(r)==c]
    if not sel: continue
    out=[f"{c:8s} rounds {len(sel):3d}"]
    for k,n in enumerate(names):
        col=[float(r[3+k]) for r in sel]; q=[float(r[3+k])/float(r[3]) for r in sel]
        out.append(f"{n.split('/')[-1]} {st.median(col):.4f} ({st.median(q):.3f})")
    print("  ".join(out))
