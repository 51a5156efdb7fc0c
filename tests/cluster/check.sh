#!/bin/sh
# SPDX-License-Identifier: MIT
# make check-cluster: the recipes of examples/cluster/ on a real scheduler
# (docs/cluster.md). Needs root and scripts/deps.sh group cluster
# (slurm-wlm, munge, parallel). In a folder of its own it makes a munge
# key and a one-node slurm.conf, starts munged, slurmctld and slurmd on
# this machine, submits examples/cluster/slurm.sh for gears in 8 tiles
# cut by ggrt plan (PLAN=1), waits, prints the tiles' times and compares
# the merge with one process's render (cmp, PNG and EXR); runs
# examples/cluster/parallel.sh in equal bands with HOSTS=: (this machine,
# no ssh); starts a private sshd on
# 127.0.0.1 (its config, host key, client key, authorized_keys, pid file
# and log in the folder, a port of its own), runs
# examples/cluster/parallel.sh over ssh to root@127.0.0.1 through it,
# with a plan sent along with each tile (PLAN=1), and compares that merge
# too; then stops every daemon it started and
# removes its folder (and /run/sshd if it made it).
#   sh tests/cluster/check.sh build/ggrt
set -u
ggrt=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
[ -x "$ggrt" ] || { echo "check-cluster: no ggrt at '$1'" >&2; exit 1; }
[ "$(id -u)" = 0 ] || { echo "check-cluster: needs root (slurmd runs jobs as their user)" >&2; exit 1; }
for c in munged mungekey slurmctld slurmd sbatch squeue sinfo parallel ssh ssh-keygen rsync \
         /usr/sbin/sshd; do
  command -v $c >/dev/null 2>&1 || { echo "check-cluster: no $c: sh scripts/deps.sh cluster" >&2; exit 1; }
done
repo=$(pwd)
# Not /tmp itself: munged refuses a socket folder others can write into.
t=$(mktemp -d /tmp/ggrt-cluster-XXXXXX)
pids=
made_run_sshd=
stop() {
  for p in $pids; do kill "$p" 2>/dev/null; done
  for p in $pids; do
    i=0; while kill -0 "$p" 2>/dev/null && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
    kill -9 "$p" 2>/dev/null
  done
  [ -n "$made_run_sshd" ] && rmdir /run/sshd 2>/dev/null
  rm -rf "$t"
}
trap stop EXIT
trap 'exit 130' INT TERM HUP
fail() { echo "check-cluster: FAIL: $*"; for f in "$t"/*.log; do echo "== $f"; tail -15 "$f"; done; exit 1; }

# ---- munge ----
mungekey --create --keyfile="$t/munge.key" || fail "mungekey"
chmod 600 "$t/munge.key"
munged --foreground --force --key-file="$t/munge.key" --socket="$t/munge.sock" \
  --pid-file="$t/munged.pid" --log-file="$t/munged.log" --seed-file="$t/munged.seed" \
  >"$t/munged.out.log" 2>&1 &
pids="$pids $!"
i=0; while [ ! -S "$t/munge.sock" ] && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
[ -S "$t/munge.sock" ] || fail "munged did not start"

# ---- slurm: one node, this machine, ports of our own ----
node=$(hostname -s)
cpus=$(getconf _NPROCESSORS_ONLN)
port=$((20000 + $$ % 20000))
mkdir -p "$t/state" "$t/spool"
cat >"$t/slurm.conf" <<CONF
ClusterName=ggrt-check
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$t/munge.sock
StateSaveLocation=$t/state
SlurmdSpoolDir=$t/spool
SlurmctldPidFile=$t/slurmctld.pid
SlurmdPidFile=$t/slurmd.pid
SlurmctldLogFile=$t/slurmctld.log
SlurmdLogFile=$t/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=check Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$t/slurm.conf"
slurmctld -D -f "$t/slurm.conf" >"$t/slurmctld.out.log" 2>&1 &
pids="$pids $!"
slurmd -D -f "$t/slurm.conf" -N "$node" >"$t/slurmd.out.log" 2>&1 &
pids="$pids $!"
i=0; state=
while [ $i -lt 300 ]; do
  state=$(sinfo -h -n "$node" -o %T 2>/dev/null)
  [ "$state" = idle ] && break
  sleep 0.2; i=$((i + 1))
done
[ "$state" = idle ] || fail "node $node is '$state', not idle, after 60 s"
echo "check-cluster: munged, slurmctld, slurmd up; node $node idle ($cpus CPUs, port $port)"

# ---- the Slurm recipe: gears, 8 tiles ----
scene=examples/scenes/spd/gears.nff
opts="--spd -s 320x240"
mkdir -p "$t/run"
cd "$t/run" || fail "cd"
cp "$repo/$scene" gears.nff
t0=$(date +%s)
# shellcheck disable=SC2086
PLAN=1 GGRT=$ggrt sh "$repo/examples/cluster/slurm.sh" gears.nff 8 slurm.png $opts >"$t/submit.log" 2>&1 ||
  fail "slurm.sh"
cat "$t/submit.log"
ids=$(sed -n 's/.*job \([0-9]*\).*job \([0-9]*\).*/\1,\2/p' "$t/submit.log")
i=0
while [ -n "$(squeue -h -j "$ids" 2>/dev/null)" ] && [ $i -lt 1500 ]; do sleep 0.2; i=$((i + 1)); done
[ -z "$(squeue -h -j "$ids" 2>/dev/null)" ] || fail "jobs $ids still queued after 300 s"
t1=$(date +%s)
echo "check-cluster: slurm: submitted to merged in $((t1 - t0)) s (Slurm's scheduling ticks, mostly); the plan's cut $(sed -n 's/^"rows":\[\(.*\)\],*$/\1/p' slurm.png.parts/plan.json); the tiles:"
cat slurm.png.parts/tile-*.log | sed 's/^/  /'
sed 's/^/  merge: /' slurm.png.parts/merge.log
[ -f slurm.png ] || fail "the merge job wrote no slurm.png"
# The tiles rendered the plan's cut: their manifest says so.
strings -n 6 slurm.png.parts/part-3.exr | grep -q '^plan 0,' || fail "slurm's tiles do not carry the plan's cut"
# shellcheck disable=SC2086
"$ggrt" render gears.nff $opts -q -o one.png && "$ggrt" render gears.nff $opts -q -o one.exr ||
  fail "one-process render"
"$ggrt" merge -q slurm.png.parts/part-*.exr -o slurm.exr || fail "merge to EXR"
cmp slurm.png one.png && cmp slurm.exr one.exr || fail "slurm's merge differs from one process"
echo "check-cluster: slurm: 8 tiles merged = one process (cmp: PNG $(wc -c <one.png) bytes, EXR $(wc -c <one.exr) bytes)"

# ---- the GNU parallel recipe, this machine as its host (no ssh) ----
# shellcheck disable=SC2086
HOSTS=: PARTS=par-local.parts GGRT=$ggrt sh "$repo/examples/cluster/parallel.sh" gears.nff 8 \
  par-local.png $opts >/dev/null || fail "parallel.sh with HOSTS=:"
cmp par-local.png one.png || fail "parallel's merge (HOSTS=:) differs from one process"
echo "check-cluster: parallel, HOSTS=: (no ssh): 8 tiles merged = one process (cmp)"

# ---- the GNU parallel recipe over ssh: a private sshd on 127.0.0.1 ----
# Everything of it in $t/ssh; -D keeps it in the foreground, a child of
# this script (its pid in $pids), -e logs to stderr, into a file here.
mkdir -p "$t/ssh"
ssh-keygen -q -t ed25519 -N '' -f "$t/ssh/host_key" || fail "ssh-keygen (host)"
ssh-keygen -q -t ed25519 -N '' -f "$t/ssh/client_key" || fail "ssh-keygen (client)"
cp "$t/ssh/client_key.pub" "$t/ssh/authorized_keys"
sport=$((port + 2))
cat >"$t/ssh/sshd_config" <<CONF
Port $sport
ListenAddress 127.0.0.1
HostKey $t/ssh/host_key
PidFile $t/ssh/sshd.pid
AuthorizedKeysFile $t/ssh/authorized_keys
PermitRootLogin prohibit-password
PubkeyAuthentication yes
PasswordAuthentication no
KbdInteractiveAuthentication no
UsePAM no
StrictModes no
PrintMotd no
CONF
# Debian's sshd wants its privilege separation folder.
[ -d /run/sshd ] || { mkdir -m 755 /run/sshd && made_run_sshd=1; }
/usr/sbin/sshd -D -e -f "$t/ssh/sshd_config" >"$t/sshd.log" 2>&1 &
pids="$pids $!"
ssh_cmd="ssh -F /dev/null -p $sport -i $t/ssh/client_key -o IdentitiesOnly=yes -o BatchMode=yes"
ssh_cmd="$ssh_cmd -o StrictHostKeyChecking=no -o UserKnownHostsFile=/dev/null -o LogLevel=ERROR"
i=0
# shellcheck disable=SC2086
while ! $ssh_cmd root@127.0.0.1 true 2>"$t/ssh-try.log" && [ $i -lt 50 ]; do sleep 0.2; i=$((i + 1)); done
# shellcheck disable=SC2086
$ssh_cmd root@127.0.0.1 true || fail "no ssh to root@127.0.0.1:$sport ($(cat "$t/ssh-try.log"))"
echo "check-cluster: sshd up on 127.0.0.1:$sport (key login as root)"
# parallel takes its ssh command from PARALLEL_SSH (as --ssh); 2/ is two
# jobs at a time on that login. The tiles go through ssh, the scene out
# and the tiles back through rsync over the same ssh.
# shellcheck disable=SC2086
PLAN=1 PARALLEL_SSH=$ssh_cmd HOSTS=2/root@127.0.0.1 GGRT=$ggrt \
  sh "$repo/examples/cluster/parallel.sh" gears.nff 8 par.png $opts >"$t/par.log" 2>&1 ||
  fail "parallel.sh over ssh"
sed 's/^/  /' "$t/par.log"
cmp par.png one.png || fail "parallel's merge (over ssh) differs from one process"
strings -n 6 par.png.parts/part-3.exr | grep -q '^plan 0,' || fail "parallel's tiles (over ssh) do not carry the plan's cut"
grep -q "Accepted publickey for root" "$t/sshd.log" || fail "sshd logged no login"
echo "check-cluster: parallel over ssh: $(grep -c 'Accepted publickey for root' "$t/sshd.log") ssh logins; 8 tiles of a plan merged = one process (cmp)"
cd "$repo" || exit 1
echo "check-cluster: ok"
