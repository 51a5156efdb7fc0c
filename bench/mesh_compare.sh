#!/bin/sh
# SPDX-License-Identifier: MIT
# The mesh scenes of scripts/make-mesh-scenes.py, ggrt against the Embree
# anchor's 16-ray eye packets, side by side: each round renders every
# scene once with each (alternating which goes first), 2 threads, ggrt
# twice: the NFF triangles the anchor reads (ggrt) and the same model as
# a mesh (ggrt-mesh: the same image and rays); the table gives the
# medians of ggrt's printed render time and the anchor's trace_s (neither
# counts reading the file or building the BVH), and the ratios
# anchor/ggrt (above 1: ggrt faster).
# Held to AVX2: GGRT_ISA=avx2 in the environment and an anchor built as
# bench/spd_isa.sh builds it (docs/performance.md, "Meshes").
# usage: sh bench/mesh_compare.sh GGRT EMBREE_BIN [RES] [ROUNDS] [DIR]
g=$1 e=$2 res=${3:-1024} rounds=${4:-3} dir=${5:-build/meshes}
[ -x "$g" ] && [ -x "$e" ] || { echo "usage: sh bench/mesh_compare.sh GGRT EMBREE_BIN [RES] [ROUNDS] [DIR]" >&2; exit 1; }
[ -f "$dir/torus-1m.nff" ] || python3 scripts/make-mesh-scenes.py "$dir" || exit 1
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
uptime
for r in $(seq "$rounds"); do for s in torus-1m knot-512k; do
  n=$dir/$s.nff
  run_g() { "$g" render "$1" -s ${res}x${res} -j 2 -o "$tmp/g.png" 2>&1 | sed -n 's/.*render \([0-9.]*\)s.*/\1/p'; }
  run_e() { "$e" -t 2 -r "$res" -p 16 -o - "$n" | sed -n 's/.*trace_s=\([0-9.]*\).*/\1/p'; }
  if [ $((r % 2)) = 1 ]; then gt=$(run_g "$n"); gm=$(run_g "$dir/$s-mesh.nff"); et=$(run_e)
  else et=$(run_e); gm=$(run_g "$dir/$s-mesh.nff"); gt=$(run_g "$n"); fi
  echo "$s $r ggrt=$gt mesh=$gm emb16=$et"
done; done | tee "$tmp/raw"
uptime
awk '{s=$1; split($3,a,"="); split($4,c,"="); split($5,b,"="); G[s,++n[s]]=a[2]; M[s,n[s]]=c[2]; E[s,n[s]]=b[2]; if(!(s in seen)){seen[s]=1; o[++m]=s}}
function med(A,s,c,  i,j,x,t){for(i=1;i<=c;i++)t[i]=A[s,i]; for(i=1;i<=c;i++)for(j=i+1;j<=c;j++)if(t[j]<t[i]){x=t[i];t[i]=t[j];t[j]=x} return (c%2)?t[(c+1)/2]:(t[c/2]+t[c/2+1])/2}
END{printf "%-10s %8s %9s %8s | %10s %15s\n","scene","ggrt","ggrt-mesh","emb-p16","emb16/ggrt","emb16/ggrt-mesh";
 for(k=1;k<=m;k++){s=o[k]; x=med(G,s,n[s]); w=med(M,s,n[s]); y=med(E,s,n[s]); printf "%-10s %8.3f %9.3f %8.3f | %10.2f %15.2f\n",s,x,w,y,y/x,y/w}}' "$tmp/raw"
