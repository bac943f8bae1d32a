#!/usr/bin/env python3
"""Snakemake's --cluster-status for Slurm: prints success, running or failed
for one job id. sacct where the cluster keeps accounting, else scontrol
(which knows a job until MinJobAge after it ends)."""
import re
import subprocess
import sys

RUNNING = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED", "RESIZING", "SIGNALING",
           "STAGE_OUT", "REQUEUE_HOLD", "REQUEUE_FED"}


def query(cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.TimeoutExpired):
        return ""


def state(jobid):
    states = query(["sacct", "-n", "-X", "-P", "-o", "State", "-j", jobid]).split()
    if states:
        return states[0].split()[0]  # "CANCELLED by 0" -> CANCELLED
    m = re.search(r"JobState=(\w+)", query(["scontrol", "show", "job", jobid]))
    return m.group(1) if m else "UNKNOWN"


s = state(sys.argv[1])
if s == "COMPLETED":
    print("success")
elif s in RUNNING:
    print("running")
else:  # FAILED, CANCELLED, TIMEOUT, OUT_OF_MEMORY, NODE_FAIL, ...; UNKNOWN: the job is gone without a record
    print(f"job {sys.argv[1]}: Slurm state {s}", file=sys.stderr)
    print("failed")
