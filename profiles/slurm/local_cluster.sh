#!/usr/bin/env bash
# A real single-node SLURM cluster on this machine, from Debian's packages, for the study's
# cluster path (profiles/slurm) and its tests:
#
#   profiles/slurm/local_cluster.sh up       start munged, MariaDB, slurmdbd, slurmctld, slurmd
#   profiles/slurm/local_cluster.sh down     stop exactly the daemons `up` started (pid files)
#   profiles/slurm/local_cluster.sh status   which of them run; sinfo
#   profiles/slurm/local_cluster.sh env      the line that points SLURM's clients at the cluster
#
# (`make slurm-up` / `make slurm-down` call it.) Everything it writes lives in $SLURM_LOCAL_DIR
# (default .slurm/ in the project, ignored by git): config, munge key, database, spool, logs and
# pid files; tests/ holds the leases of the test runs that use the cluster (tests/slurm_cluster.py:
# a test run stops the cluster only if it started it). No systemd, no /etc: every daemon is started by hand with its config path, as the
# user who runs this script (root in CI). SLURM's clients (sbatch, squeue, sacct, and so the
# Snakemake plugin) find the cluster through SLURM_CONF=$SLURM_LOCAL_DIR/etc/slurm.conf.
#
# Ports: slurmctld 6817, slurmd 6818, slurmdbd 6819 (SLURM's defaults), MariaDB 6820 on
# 127.0.0.1 only (not 3306, so that a MariaDB or MySQL of the machine's own is left alone).
set -uo pipefail

PROJECT=$(cd "$(dirname "$0")/../.." && pwd)
STATE=${SLURM_LOCAL_DIR:-$PROJECT/.slurm}
ETC=$STATE/etc RUN=$STATE/run LOG=$STATE/log SPOOL=$STATE/spool DB=$STATE/mysql
CLUSTER=hertz ACCOUNT=hertz PARTITION=local
CTLD_PORT=6817 SLURMD_PORT=6818 DBD_PORT=6819 DB_PORT=6820
USER_NAME=$(id -un)
NODE=$(hostname -s)
export SLURM_CONF=$ETC/slurm.conf
# Where SLURM's clients look for the config when SLURM_CONF is unset, after /etc/slurm/slurm.conf:
# slurmd's configless cache. A job's inner `srun` needs it: snakemake-executor-plugin-slurm-jobstep
# (0.6) starts that srun with every SLURM_* variable removed, SLURM_CONF included.
CLIENT_CONF=/run/slurm/conf/slurm.conf
# Each daemon: its pid file and the executable name /proc/<pid>/comm shows for it.
DAEMONS=(munged mariadbd slurmdbd slurmctld slurmd)

say() { echo "local SLURM cluster: $*"; }
die() { echo "local SLURM cluster: error: $*" >&2; exit 1; }

pidfile() { echo "$RUN/$1.pid"; }

# The pid of daemon $1 when its pid file names a live process of that name; nothing otherwise.
# A pid file whose process is gone (a crash, a reboot) is stale: say so and remove it.
running_pid() {
  local f pid comm
  f=$(pidfile "$1")
  [ -s "$f" ] || return 0
  pid=$(tr -dc 0-9 <"$f")
  comm=$(cat "/proc/$pid/comm" 2>/dev/null || true)
  if [ -n "$pid" ] && [ "$comm" = "$1" ]; then
    echo "$pid"
  else
    say "stale pid file $f (pid ${pid:-?} is ${comm:+a $comm, }not a running $1): removed" >&2
    rm -f "$f"
  fi
}

# Refuse to start a daemon on a port another process already listens on.
port_free() {  # port, daemon
  if (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; then
    die "port $1 (for $2) is in use by another process on this machine (see: ss -ltnp 'sport = :$1');
  stop it, or that cluster, first: this script only stops daemons it started itself (pid files in $RUN)"
  fi
}

wait_for() {  # seconds, description, command...: true once the command succeeds within the time
  local deadline=$((SECONDS + $1)); shift 2
  until "$@" >/dev/null 2>&1; do
    [ $SECONDS -lt $deadline ] || return 1
    sleep 0.2
  done
}

require() {
  local missing=()
  for exe in munged mungekey mariadbd mariadb-install-db mariadb slurmctld slurmd slurmdbd sinfo sacctmgr; do
    command -v "$exe" >/dev/null || missing+=("$exe")
  done
  [ ${#missing[@]} = 0 ] || die "missing ${missing[*]}; install Debian's packages:
  sudo apt-get install -y slurm-wlm slurmdbd munge mariadb-server   (or: make slurm-up, which does)"
}

write_config() {
  mkdir -p "$ETC" "$RUN" "$LOG" "$SPOOL/ctld" "$SPOOL/d" "$DB"
  chmod 700 "$RUN" "$ETC"   # munged refuses a socket directory others can write to
  # The node as slurmd sees this machine (its real CPUs and memory).
  local node
  node=$(slurmd -C | head -1) || die "slurmd -C could not read this machine's CPUs and memory"
  node=${node/NodeName=$NODE/NodeName=$NODE NodeAddr=127.0.0.1}
  cat >"$ETC/slurm.conf" <<EOF
# Written by profiles/slurm/local_cluster.sh: a single-node cluster for the study's tests.
ClusterName=$CLUSTER
SlurmctldHost=$NODE(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
# Every daemon and every job runs as the user who started the cluster.
SlurmUser=$USER_NAME
SlurmdUser=$USER_NAME
AuthType=auth/munge
AuthInfo=socket=$RUN/munge.socket
CredType=cred/munge
StateSaveLocation=$SPOOL/ctld
SlurmdSpoolDir=$SPOOL/d
SlurmctldPidFile=$(pidfile slurmctld)
SlurmdPidFile=$(pidfile slurmd)
SlurmctldLogFile=$LOG/slurmctld.log
SlurmdLogFile=$LOG/slurmd.log
# Containers rarely delegate cgroups and have no systemd, so nothing here needs them:
#  proctrack/linuxproc  finds a job's processes by their parent pids (proctrack/cgroup needs a
#                       writable cgroup tree; the engines never leave their job's process tree);
#  task/none            no CPU binding or cgroup confinement (task/affinity and task/cgroup
#                       need both); srun's --cpu-bind is then a no-op;
#  select/cons_tres     CPUs and memory are consumable, so --cpus-per-task and --mem count;
#  jobacct_gather/linux polls every second what a job's processes use: sacct's MaxRSS, and
#                       OverMemoryKill kills a step over its --mem, the memory limit that works
#                       without the cgroup memory controller.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
JobAcctGatherType=jobacct_gather/linux
JobAcctGatherFrequency=task=1
JobAcctGatherParams=OverMemoryKill
# No PMI server for srun by default: the project's engines start their own MPI (engines.engine_process).
MpiDefault=none
SwitchType=switch/none
# Job accounting in slurmdbd + MariaDB: sacct answers for finished jobs (the Snakemake plugin's
# default status query), as on a production cluster.
AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=127.0.0.1
AccountingStoragePort=$DBD_PORT
# (For slurmdbd, "Pass" is the munge socket its clients authenticate through.)
AccountingStoragePass=$RUN/munge.socket
# Keep each job's --comment, where the Snakemake plugin names its rule and wildcards
# (sacct -o JobID,State,Comment%60 then says which job ran what).
AccountingStoreFlags=job_comment
JobCompType=jobcomp/none
# Finished jobs stay in squeue for 5 min (the plugin's squeue status needs >= 3x its wait).
MinJobAge=300
# A job past its time limit gets SIGTERM, then SIGKILL this many seconds later.
KillWait=10
ReturnToService=2
SchedulerType=sched/backfill
$node
PartitionName=$PARTITION Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
  cat >"$ETC/slurmdbd.conf" <<EOF
# Written by profiles/slurm/local_cluster.sh
AuthType=auth/munge
AuthInfo=socket=$RUN/munge.socket
DbdHost=localhost
DbdAddr=127.0.0.1
DbdPort=$DBD_PORT
SlurmUser=$USER_NAME
PidFile=$(pidfile slurmdbd)
LogFile=$LOG/slurmdbd.log
StorageType=accounting_storage/mysql
StorageHost=127.0.0.1
StoragePort=$DB_PORT
StorageUser=slurm
StoragePass=slurm-local
StorageLoc=slurm_acct_db
EOF
  chmod 600 "$ETC/slurmdbd.conf"   # slurmdbd refuses a config others can read (it holds a password)
}

# What is at CLIENT_CONF: nothing ("none"), this cluster's link ("ours"), a link this script made
# for another local cluster (another clone's, or another SLURM_LOCAL_DIR's) that still runs
# ("running") or no longer does ("stale": its config is gone, or the slurmctld its config names
# is not running), or anything else ("foreign": a configless slurmd's cache, say). /run outlives
# the daemons (a session or a CI job that ended without `down`, a killed test run), and a stale
# link must not block every later cluster on the machine.
client_config_state() {
  if [ ! -e "$CLIENT_CONF" ] && [ ! -L "$CLIENT_CONF" ]; then echo none; return; fi
  local target pidf pid
  target=$(readlink "$CLIENT_CONF")
  if [ "$target" = "$ETC/slurm.conf" ]; then echo ours; return; fi
  if [ -L "$CLIENT_CONF" ] && [ ! -e "$target" ]; then echo stale; return; fi
  if [ -z "$target" ] || ! head -1 "$target" | grep -q '^# Written by profiles/slurm/local_cluster.sh'; then
    echo foreign; return
  fi
  pidf=$(sed -n 's/^SlurmctldPidFile=//p' "$target")
  pid=$(cat "$pidf" 2>/dev/null | tr -dc 0-9)
  if [ -n "$pid" ] && [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = slurmctld ]; then echo running; else echo stale; fi
}

# Point the clients that run without SLURM_CONF (a job's inner srun) at this cluster's config: a
# link at CLIENT_CONF. Refused where the machine has a SLURM config of its own, which they would
# read instead (/etc/slurm/slurm.conf comes first) or which the link would replace, and where
# another local cluster still runs; a link left by one that has stopped is replaced.
check_client_config() {
  [ -e /etc/slurm/slurm.conf ] && die "this machine has a SLURM config of its own, /etc/slurm/slurm.conf;
  a job's srun (started by the Snakemake plugin without SLURM_CONF) would read it instead of $ETC/slurm.conf"
  local target
  target=$(readlink "$CLIENT_CONF")
  case $(client_config_state) in
    running) die "$CLIENT_CONF links to $target, the config of another local cluster that still runs;
  stop it first: SLURM_LOCAL_DIR=$(dirname "$(dirname "$target")") $0 down" ;;
    foreign) die "$CLIENT_CONF exists and is not this cluster's (a configless slurmd of another cluster?); not replaced" ;;
  esac
  return 0
}

link_client_config() {
  if [ "$(client_config_state)" = stale ]; then
    say "replacing $CLIENT_CONF, a link to $(readlink "$CLIENT_CONF") left by a local cluster that no longer runs"
  fi
  local sudo=""
  [ "$(id -u)" = 0 ] || sudo=sudo   # /run is root's: the one step of a user's cluster that needs it
  $sudo mkdir -p "$(dirname "$CLIENT_CONF")" && $sudo ln -sfn "$ETC/slurm.conf" "$CLIENT_CONF" \
    || die "cannot write $CLIENT_CONF (as root, or through sudo): a job's srun finds the cluster's config there"
}

unlink_client_config() {
  local sudo=""
  [ "$(id -u)" = 0 ] || sudo=sudo
  if [ "$(readlink "$CLIENT_CONF" 2>/dev/null)" = "$ETC/slurm.conf" ]; then $sudo rm -f "$CLIENT_CONF"; fi
  return 0
}

start_munge() {
  [ -n "$(running_pid munged)" ] && return 0
  if [ ! -s "$ETC/munge.key" ]; then
    mungekey --create --keyfile="$ETC/munge.key" || die "mungekey could not create $ETC/munge.key"
  fi
  chmod 600 "$ETC/munge.key"
  # --force: munged otherwise refuses to run as root, which CI is.
  munged --force --socket="$RUN/munge.socket" --key-file="$ETC/munge.key" --pid-file="$(pidfile munged)" \
         --log-file="$LOG/munged.log" --seed-file="$STATE/munged.seed" \
    || die "munged did not start; see $LOG/munged.log"
  wait_for 10 munge test -S "$RUN/munge.socket" || die "munged's socket did not appear; see $LOG/munged.log"
}

start_mariadb() {
  [ -n "$(running_pid mariadbd)" ] && return 0
  port_free $DB_PORT MariaDB
  if [ ! -d "$DB/mysql" ]; then
    mariadb-install-db --no-defaults --datadir="$DB" --user="$USER_NAME" --auth-root-authentication-method=socket \
      --skip-test-db >"$LOG/mariadb-install.log" 2>&1 || die "mariadb-install-db failed; see $LOG/mariadb-install.log"
  fi
  nohup mariadbd --no-defaults --datadir="$DB" --user="$USER_NAME" --socket="$RUN/mysqld.sock" \
    --pid-file="$(pidfile mariadbd)" --port=$DB_PORT --bind-address=127.0.0.1 --skip-name-resolve \
    --log-error="$LOG/mariadb.log" --innodb-buffer-pool-size=128M --innodb-lock-wait-timeout=900 </dev/null >/dev/null 2>&1 &
  wait_for 60 MariaDB mariadb --no-defaults -S "$RUN/mysqld.sock" -u "$USER_NAME" -e 'select 1' \
    || die "MariaDB did not answer within 60 s; see $LOG/mariadb.log"
  mariadb --no-defaults -S "$RUN/mysqld.sock" -u "$USER_NAME" -e "
    CREATE USER IF NOT EXISTS 'slurm'@'127.0.0.1' IDENTIFIED BY 'slurm-local';
    CREATE USER IF NOT EXISTS 'slurm'@'localhost' IDENTIFIED BY 'slurm-local';
    GRANT ALL ON slurm_acct_db.* TO 'slurm'@'127.0.0.1';
    GRANT ALL ON slurm_acct_db.* TO 'slurm'@'localhost';" || die "could not create MariaDB's user slurm"
}

start_slurmdbd() {
  [ -n "$(running_pid slurmdbd)" ] && return 0
  port_free $DBD_PORT slurmdbd
  slurmdbd || die "slurmdbd did not start; see $LOG/slurmdbd.log"
  wait_for 30 slurmdbd sacctmgr -n show cluster || die "slurmdbd did not answer within 30 s; see $LOG/slurmdbd.log"
  # The cluster, an account and the user in it: sbatch --account and the plugin's default
  # account lookup (sacctmgr show user) then work as on a production cluster.
  sacctmgr -i -Q add cluster "$CLUSTER" >/dev/null 2>&1 || true
  sacctmgr -i -Q add account "$ACCOUNT" Cluster="$CLUSTER" Description="hertz study" Organization=local >/dev/null 2>&1 || true
  sacctmgr -i -Q add user "$USER_NAME" DefaultAccount="$ACCOUNT" Cluster="$CLUSTER" >/dev/null 2>&1 || true
}

start_slurm() {
  if [ -z "$(running_pid slurmctld)" ]; then
    port_free $CTLD_PORT slurmctld
    slurmctld -f "$ETC/slurm.conf" || die "slurmctld did not start; see $LOG/slurmctld.log"
  fi
  if [ -z "$(running_pid slurmd)" ]; then
    port_free $SLURMD_PORT slurmd
    slurmd -f "$ETC/slurm.conf" || die "slurmd did not start; see $LOG/slurmd.log"
  fi
  # A node that was down (a stopped slurmd, a drain from an earlier test) comes back.
  wait_for 30 slurmctld scontrol ping || die "slurmctld did not answer within 30 s; see $LOG/slurmctld.log"
  if sinfo -h -n "$NODE" -o %t 2>/dev/null | grep -qE 'drain|down'; then
    scontrol update NodeName="$NODE" State=RESUME >/dev/null 2>&1 || true
  fi
  wait_for 60 "the node idle" bash -c "sinfo -h -n '$NODE' -o %t | grep -qx idle" \
    || die "node $NODE did not become idle within 60 s (sinfo: $(sinfo -h -o '%t %E' 2>&1)); see $LOG/slurmd.log"
}

# Every port a daemon still to start needs must be free before the first one starts: a second
# cluster (another SLURM_LOCAL_DIR) or a SLURM of the machine's own is refused with nothing started.
check_ports() {
  [ -n "$(running_pid mariadbd)" ] || port_free $DB_PORT MariaDB
  [ -n "$(running_pid slurmdbd)" ] || port_free $DBD_PORT slurmdbd
  [ -n "$(running_pid slurmctld)" ] || port_free $CTLD_PORT slurmctld
  [ -n "$(running_pid slurmd)" ] || port_free $SLURMD_PORT slurmd
}

all_running() {
  for d in "${DAEMONS[@]}"; do [ -n "$(running_pid "$d" 2>/dev/null)" ] || return 1; done
}

up() {
  require
  # Anyone but a test run (tests/slurm_cluster.py, which sets HERTZ_TEST_RUN) takes the cluster over
  # from the tests: their leases go, and no test run stops it when it ends.
  [ -n "${HERTZ_TEST_RUN:-}" ] || rm -f "$STATE"/tests/run-*
  if all_running && sinfo -h -n "$NODE" -o %t 2>/dev/null | grep -qx idle; then
    say "already running (node $NODE idle; state in $STATE)"
  else
    check_client_config
    check_ports
    write_config
    link_client_config
    start_munge
    start_mariadb
    start_slurmdbd
    start_slurm
    say "up: node $NODE idle, $(sinfo -h -o '%c CPUs, %m MB') in partition $PARTITION (state in $STATE)"
  fi
  echo "SLURM's clients find it through: export SLURM_CONF=$SLURM_CONF"
}

down() {
  local stopped=()
  # Reverse order of start: the node, the controller, accounting, its database, authentication.
  for ((i = ${#DAEMONS[@]} - 1; i >= 0; i--)); do
    local d=${DAEMONS[$i]} pid
    pid=$(running_pid "$d")
    [ -n "$pid" ] || continue
    kill -TERM "$pid" 2>/dev/null
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then kill -KILL "$pid" 2>/dev/null; fi
    rm -f "$(pidfile "$d")"
    stopped+=("$d")
  done
  unlink_client_config
  if [ ${#stopped[@]} = 0 ]; then say "not running (no live pid files in $RUN)"; else say "stopped ${stopped[*]}"; fi
}

status() {
  for d in "${DAEMONS[@]}"; do
    pid=$(running_pid "$d")
    if [ -n "$pid" ]; then echo "$d: running (pid $pid)"; else echo "$d: not running"; fi
  done
  all_running && sinfo
}

case "${1:-}" in
  up) up ;;
  down) down ;;
  status) status ;;
  env) echo "export SLURM_CONF=$SLURM_CONF" ;;
  *) echo "usage: $0 up|down|status|env" >&2; exit 2 ;;
esac
