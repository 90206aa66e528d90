#!/usr/bin/env python3
"""Where `cornell`'s remaining error lies under `mis` and `bdpt`: the mean squared error (against
a `bdpt` reference of 2 x 1,024 spp, its noise subtracted) split between the pixels whose
footprint sees the glass ball (the camera's geometry, 5 x 5 points a pixel) and the rest.
80 x 80, 256 spp, seed 3, 2 threads. Prints its figures (results/bdpt.md quotes them).

    benches/bdpt_split.py [--bin target/release/raypool]
"""
import struct,subprocess,sys,os,math,tempfile
BIN = sys.argv[sys.argv.index("--bin") + 1] if "--bin" in sys.argv else "target/release/raypool"
def read_pfm(path):
    with open(path,"rb") as f:
        f.readline(); w,h=map(int,f.readline().split()); scale=float(f.readline())
        d=struct.unpack(("<" if scale<0 else ">")+"%df"%(w*h*3), f.read(w*h*12))
    # to top-down rows
    rows=[d[(h-1-y)*w*3:(h-y)*w*3] for y in range(h)]
    return w,h,[v for r in rows for v in r]
def render(ls,spp,seed,out):
    line=subprocess.run([BIN,"render","--scene","cornell","--width","80","--spp",str(spp),"--seed",str(seed),"--light-sampling",ls,"--threads","2","--out",out],capture_output=True,text=True,check=True).stderr
    return line.strip()
tmp=tempfile.mkdtemp()
for seed in (101,102): render("bdpt",1024,seed,f"{tmp}/ref{seed}.pfm")
W=80; c=(190.0,90.0,190.0); R=90.0
def hits(x,y):
    # pixel-space point (x, y) from the top-left, pinhole at (278,278,-800)
    t=(569.2-7.28*x, 569.2-7.28*y, 0.0); o=(278.0,278.0,-800.0)
    d=[t[k]-o[k] for k in range(3)]; n=math.sqrt(sum(v*v for v in d)); d=[v/n for v in d]
    oc=[o[k]-c[k] for k in range(3)]; b=sum(oc[k]*d[k] for k in range(3)); cc=sum(v*v for v in oc)-R*R
    return b*b-cc>0
glass=[any(hits(i+(a+0.5)/5,j+(b+0.5)/5) for a in range(5) for b in range(5)) for j in range(W) for i in range(W)]
_,_,r1=read_pfm(f"{tmp}/ref101.pfm"); _,_,r2=read_pfm(f"{tmp}/ref102.pfm")
ref=[(x+y)/2 for x,y in zip(r1,r2)]
def split(img, sq):
    e=[0.0,0.0]
    for k in range(W*W):
        s=sum(sq(img,k,ch) for ch in range(3))
        e[0 if glass[k] else 1]+=s
    return [v/(3*W*W) for v in e]
noise=split(None, lambda _,k,ch:(r1[3*k+ch]-r2[3*k+ch])**2/4)
print("pixels seeing the glass: %d of %d; reference noise (bdpt 2x1024 spp) glass %.2e, rest %.2e"%(sum(glass),W*W,*noise))
for ls in ("mis","bdpt"):
    line=render(ls,256,3,f"{tmp}/{ls}.pfm"); _,_,a=read_pfm(f"{tmp}/{ls}.pfm")
    e=split(a, lambda a,k,ch:(a[3*k+ch]-ref[3*k+ch])**2)
    e=[x-n for x,n in zip(e,noise)]
    print("%s 256 spp (%s): MSE from pixels seeing the glass %.3e, from the rest %.3e, total %.3e"%(ls,line.split("threads 2: ")[1].split(",")[0],e[0],e[1],e[0]+e[1]))
