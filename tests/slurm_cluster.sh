#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, from Debian's slurm-wlm and
# munge, for the workflow tests: everything (key, config, state, logs,
# sockets) under one folder, on ports of its own, so it touches no system
# Slurm.
#
#   tests/slurm_cluster.sh start DIR   # exit 0: up, and DIR/env sets SLURM_CONF for its clients;
#                                      # exit 77: this machine cannot run it (says why)
#   tests/slurm_cluster.sh stop DIR
#
# The daemons run as the calling user, who must be root (slurmd starts jobs
# as their owner); accounting is off, so sacct has nothing and job states come
# from scontrol.
set -u
cmd="${1:-}"; D="${2:-}"
[ -n "$cmd" ] && [ -n "$D" ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

stop() {
  for p in slurmd slurmctld munged; do
    [ -s "$D/$p.pid" ] && kill "$(cat "$D/$p.pid")" 2>/dev/null
  done
  sleep 1
  for p in slurmd slurmctld munged; do
    [ -s "$D/$p.pid" ] && kill -9 "$(cat "$D/$p.pid")" 2>/dev/null
    rm -f "$D/$p.pid"
  done
  return 0
}

skip() { echo "slurm cluster: $*" >&2; stop; exit 77; }

if [ "$cmd" = stop ]; then stop; exit 0; fi
[ "$cmd" = start ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

for b in munged mungekey slurmctld slurmd sbatch scontrol sinfo; do
  command -v "$b" >/dev/null || [ -x "/usr/sbin/$b" ] || skip "$b not installed (Debian: slurm-wlm, munge)"
done
[ "$(id -u)" = 0 ] || skip "the daemons need root to start jobs"
PATH="$PATH:/usr/sbin"
mkdir -p "$D"/{state,spool,log}
D=$(cd "$D" && pwd)

# Ports of its own, free now (a system Slurm keeps 6817/6818).
free_port() {
  local p
  for p in $(seq "$1" $(($1 + 200))); do
    (exec 3<>/dev/tcp/127.0.0.1/"$p") 2>/dev/null || { echo "$p"; return; }
  done
}
ctld_port=$(free_port 16817); d_port=$(free_port $((ctld_port + 1)))
host=$(hostname -s)
cpus=$(nproc)
mem_mb=$(awk '/MemTotal/ {print int($2 / 1024 * 0.9)}' /proc/meminfo)

mungekey --create --keyfile "$D/munge.key" --force >/dev/null 2>&1 || skip "mungekey failed"
chmod 600 "$D/munge.key"
munged --force --key-file "$D/munge.key" --socket "$D/munge.socket" --pid-file "$D/munged.pid" \
  --log-file "$D/log/munged.log" --seed-file "$D/munge.seed" 2>"$D/log/munged.err" ||
  skip "munged did not start: $(cat "$D/log/munged.err")"

cat > "$D/slurm.conf" <<EOF
ClusterName=brdfshot-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=$(id -un)
SlurmdUser=$(id -un)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$D/munge.socket
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
SlurmctldLogFile=$D/log/slurmctld.log
SlurmdLogFile=$D/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SchedulerParameters=sched_min_interval=100000
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MinJobAge=600
MpiDefault=none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=short Nodes=$host Default=YES MaxTime=60 State=UP
PartitionName=long Nodes=$host MaxTime=INFINITE State=UP
EOF
echo "export SLURM_CONF=$D/slurm.conf" > "$D/env"
export SLURM_CONF="$D/slurm.conf"

slurmctld -f "$D/slurm.conf" 2>"$D/log/slurmctld.err" || skip "slurmctld did not start: $(tail -3 "$D/log/slurmctld.err")"
slurmd -f "$D/slurm.conf" 2>"$D/log/slurmd.err" || skip "slurmd did not start: $(tail -3 "$D/log/slurmd.err")"
for _ in $(seq 60); do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -1)
  case "$state" in idle|mix|alloc) break ;; esac
  sleep 0.5
done
case "$state" in idle|mix|alloc) ;; *) skip "the node did not come up (state '${state:-none}'): $(tail -3 "$D/log/slurmd.log" 2>/dev/null)" ;; esac
out=$(srun -p short -N1 -n1 -t 1 echo slurm-ok 2>&1) || skip "a test job did not run: $out"
[ "$out" = slurm-ok ] || skip "a test job printed '$out'"
echo "slurm cluster up: $host, $cpus CPUs, $mem_mb MB, SLURM_CONF=$D/slurm.conf"
