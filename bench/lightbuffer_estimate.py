#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Estimate of a light buffer for gears (Haines and Greenberg, "The Light
# Buffer", IEEE CG&A 1986), made before deciding whether to build one
# (docs/performance.md, "What coloured shadows cost"): per light, a cube
# of R x R cells per face round the light; each triangle of gears.nff
# (polygons fan-triangulated) is listed in every cell its projected box
# covers. For 20,000 points spread over the triangles by area it prints
# how many listed triangles are nearer the light than the point: what a
# shadow query would have to test. Triangles whose corners project onto
# different faces are left out (counted as "straddle"), so the figures
# are a lower bound.
#   python3 bench/lightbuffer_estimate.py [R]   (from the top of a checkout; R = 128)
import math
import random
import sys
from collections import defaultdict

R = int(sys.argv[1]) if len(sys.argv) > 1 else 128
lines=open('examples/scenes/spd/gears.nff').read().split('\n')
tris=[]; i=0
while i<len(lines):
    w=lines[i].split()
    if w and w[0]=='p':
        n=int(w[1]); vs=[tuple(map(float,lines[i+1+k].split())) for k in range(n)]
        for k in range(1,n-1): tris.append((vs[0],vs[k],vs[k+1]))
        i+=n+1
    else: i+=1
print(len(tris),'triangles')
for L in [(2,4,4),(-1.111,-2.121,2.626)]:
    cells=defaultdict(list); bad=0
    def proj(p):
        d=[p[0]-L[0],p[1]-L[1],p[2]-L[2]]
        a=max(range(3),key=lambda k:abs(d[k])); s=1 if d[a]>0 else 0
        u,v=[d[k]/abs(d[a]) for k in range(3) if k!=a]
        return (a,s),u,v,math.sqrt(sum(x*x for x in d))
    for ti,t in enumerate(tris):
        ps=[proj(p) for p in t]
        if len(set(p[0] for p in ps))>1: bad+=1; continue
        f=ps[0][0]; us=[p[1] for p in ps]; vs=[p[2] for p in ps]; dmin=min(p[3] for p in ps)
        u0=int((min(us)+1)/2*R); u1=int((max(us)+1)/2*R); v0=int((min(vs)+1)/2*R); v1=int((max(vs)+1)/2*R)
        for u in range(max(u0,0),min(u1,R-1)+1):
            for v in range(max(v0,0),min(v1,R-1)+1): cells[(f,u,v)].append((dmin,ti))
    tot=sum(len(c) for c in cells.values())
    random.seed(1); cnt=[]; 
    for s in range(20000):
        ti=random.randrange(len(tris)); a,b,c=tris[ti]; r1,r2=random.random(),random.random()
        if r1+r2>1: r1,r2=1-r1,1-r2
        P=tuple(a[k]+r1*(b[k]-a[k])+r2*(c[k]-a[k]) for k in range(3))
        f,u,v,dist=proj(P); cu=min(int((u+1)/2*R),R-1); cv=min(int((v+1)/2*R),R-1)
        cnt.append(sum(1 for (dm,tj) in cells.get((f,cu,cv),[]) if dm<dist and tj!=ti))
    cnt.sort()
    print('light',L,'R',R,'straddle',bad,'entries',tot,'cells',len(cells),'mean cand',sum(cnt)/len(cnt),'median',cnt[len(cnt)//2],'p90',cnt[int(.9*len(cnt))])
