import sys, statistics as st
rows=[list(map(float,l.split())) for l in open(sys.argv[1]) if len(l.split())>=5]
names=sys.argv[2:]
for cls,sel in (('far',lambda r:r[1]>=250 and r[2]>=250),('near',lambda r:r[1]<250 and r[2]<250)):
  s=[r for r in rows if sel(r)]
  if not s: continue
  print(cls,len(s),' '.join('%s %.4f (x%.3f)'%(n,st.median(r[3+k] for r in s),st.median(r[3+k]/r[3] for r in s)) for k,n in enumerate(names)))
