#!/usr/bin/env bash
# A real Slurm test of `dem sweep` (issue 21, item 5): starts a one-node Slurm cluster on this
# machine (munged, slurmctld, slurmd; slurm.conf generated from `slurmd -C`, in a temporary
# folder through SLURM_CONF, so no file of /etc/slurm is touched), plans the example study
# examples/studies/cutting-demo.json, submits its job array with `sbatch --wait`, collects the
# table, and compares it byte for byte (timing columns left out: `collect --no-timing`) with a
# local `dem sweep run --jobs 2` of the same study. Stops the daemons it started. Exit code 0 if
# the tables are equal, 1 if not or if anything failed.
#
# Needs root (apt-get and the daemons): installs Debian's slurm-wlm and munge if missing, and
# creates /etc/munge/munge.key if there is none.
#
#   scripts/slurm-check.sh            # builds `dem` (cargo build --release -p dem-cli)
#   DEM=/path/to/dem scripts/slurm-check.sh
#   KEEP=1 ...                        # keep the work folder (printed) for a look
#   STUDY=path/study.json TIME=01:00:00 ...   # another study (and the tasks' time limit)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
study=$(readlink -f "${STUDY:-$root/examples/studies/cutting-demo.json}")
[ -f "$study" ] || { echo "slurm-check: STUDY $study: no such file" >&2; exit 1; }
start=$(date +%s)
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }
say() { printf '[slurm-check %3ds] %s\n' "$(($(date +%s) - start))" "$*"; }

if [ "$(id -u)" != 0 ]; then
    echo "slurm-check: needs root (apt-get, munged, slurmctld, slurmd)" >&2
    exit 1
fi

if [ -z "${DEM:-}" ]; then
    say "building dem (cargo build --release -p dem-cli)"
    (cd "$root" && cargo build --release -p dem-cli --quiet)
    DEM="$root/target/release/dem"
fi
DEM=$(readlink -f "$DEM")
[ -x "$DEM" ] || { echo "slurm-check: $DEM is not an executable" >&2; exit 1; }

if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null \
    || ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    say "installing slurm-wlm and munge (apt-get)"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    # (Without an init system the packages' service starts fail harmlessly: we start the
    # daemons ourselves below.)
    apt-get install -y -qq slurm-wlm munge >/dev/null
fi
say "$(slurmctld -V), munge $(munged -V 2>&1 | awk '{print $2}')"

work=$(mktemp -d /tmp/slurm-check.XXXXXX)
chmod 755 "$work"
export SLURM_CONF="$work/slurm.conf"
started_munge=""
cleanup() {
    set +e
    for p in slurmd slurmctld; do
        if [ -f "$work/$p.pid" ]; then
            kill "$(cat "$work/$p.pid")" 2>/dev/null
        fi
    done
    # Wait for them to go (the ports are reused by the next run).
    for _ in $(seq 50); do
        alive=0
        for p in slurmd slurmctld; do
            [ -f "$work/$p.pid" ] && kill -0 "$(cat "$work/$p.pid")" 2>/dev/null && alive=1
        done
        [ "$alive" = 0 ] && break
        sleep 0.1
    done
    if [ -n "$started_munge" ] && [ -f /run/munge/munged.pid ]; then
        kill "$(cat /run/munge/munged.pid)" 2>/dev/null
    fi
    if [ -z "${KEEP:-}" ]; then rm -rf "$work"; else echo "work folder kept: $work"; fi
}
trap cleanup EXIT

# munge: a key, then the daemon (as the munge user) unless one answers already.
if [ ! -s /etc/munge/munge.key ]; then
    say "creating /etc/munge/munge.key"
    mkdir -p /etc/munge
    dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none
fi
chown munge:munge /etc/munge/munge.key
chmod 400 /etc/munge/munge.key
mkdir -p /run/munge /var/lib/munge /var/log/munge
chown munge:munge /run/munge /var/lib/munge /var/log/munge
if ! munge -n </dev/null 2>/dev/null | unmunge >/dev/null 2>&1; then
    runuser -u munge -- munged
    started_munge=1
    say "munged started"
fi
munge -n </dev/null | unmunge >/dev/null

# slurm.conf for one node: this machine's CPUs and memory as slurmd sees them.
host=$(hostname -s)
node=$(slurmd -C | head -1 | sed "s/^NodeName=[^ ]*/NodeName=$host NodeAddr=127.0.0.1/")
mkdir -p "$work/ctld" "$work/d" "$work/log"
cat >"$SLURM_CONF" <<EOF
ClusterName=demcheck
SlurmctldHost=$host(127.0.0.1)
AuthType=auth/munge
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
StateSaveLocation=$work/ctld
SlurmdSpoolDir=$work/d
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
$node State=UNKNOWN
PartitionName=check Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
say "slurm.conf node: $node"

slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for i in $(seq 100); do
    state=$(sinfo -h -N -o '%T' 2>/dev/null | head -1 || true)
    [ "$state" = idle ] && break
    if [ "$i" = 100 ]; then
        echo "slurm-check: the node did not come up (state '$state'); logs:" >&2
        tail -20 "$work/log/slurmctld.log" "$work/log/slurmd.log" >&2
        exit 1
    fi
    sleep 0.2
done
say "cluster up: $(sinfo -h -o '%P %a %D %T %c')"

# The study on Slurm: one array task per case.
"$DEM" sweep plan "$study" --out "$work/slurm" --time "${TIME:-00:10:00}" >/dev/null
n=$(wc -l <"$work/slurm/cases.jsonl")
say "submitting $n array tasks: $(grep -- '--array' "$work/slurm/slurm.sbatch")"
t0=$(date +%s.%N)
if ! sbatch --wait --quiet "$work/slurm/slurm.sbatch"; then
    echo "slurm-check: the job array failed; task logs:" >&2
    tail -n 20 "$work"/slurm/logs/*.out >&2 || true
    exit 1
fi
t1=$(date +%s.%N)
say "job array done in $(secs "$t0" "$t1") s; $(ls "$work"/slurm/logs/*.out | wc -l) task logs"
"$DEM" sweep status "$work/slurm"

# The same study here.
"$DEM" sweep plan "$study" --out "$work/local" >/dev/null
t0=$(date +%s.%N)
"$DEM" sweep run "$work/local" --jobs 2 2>/dev/null | tail -1
t1=$(date +%s.%N)
say "local run (--jobs 2) done in $(secs "$t0" "$t1") s"
"$DEM" sweep status "$work/local" | tail -n +2

status=0
for f in table.csv table.json; do
    "$DEM" sweep collect "$work/slurm" --out "$work/slurm-$f" --no-timing >/dev/null
    "$DEM" sweep collect "$work/local" --out "$work/local-$f" --no-timing >/dev/null
done
for f in table.csv table.aggregates.csv table.json; do
    if cmp -s "$work/slurm-$f" "$work/local-$f"; then
        say "$f: identical ($(wc -c <"$work/slurm-$f") bytes)"
    else
        say "$f: DIFFERS"
        diff "$work/slurm-$f" "$work/local-$f" | head -20 || true
        status=1
    fi
done
# Every case ran once, by an array task (its log names a Slurm step's pid).
for d in "$work"/slurm/cases/*/; do
    a=$(grep -c '^=== dem sweep run: attempt' "$d/log.txt")
    [ "$a" = 1 ] || { say "$d: $a attempts"; status=1; }
done
echo "--- slurm table ($work/slurm-table.csv)"
cat "$work/slurm-table.csv"
echo "--- aggregates over seeds"
cat "$work/slurm-table.aggregates.csv"
if [ "$status" = 0 ]; then
    say "PASS: the Slurm job array's table equals the local run's"
else
    say "FAIL"
fi
exit "$status"
