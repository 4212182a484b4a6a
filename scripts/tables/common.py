"""What the table scripts share: running a packbench command, and timing one with GNU time
(/usr/bin/time, so the peak memory is the command's, not this interpreter's)."""

import json
import subprocess
import sys

# Wall s, user s, system s, peak resident KB.
TIME_FORMAT = "%e %U %S %M"


def run(cmd, env=None):
    """The command's standard output; exits with its last error lines when it fails."""
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed: {r.stderr.strip()[-600:]}")
    return r.stdout


def run_timed(cmd, times, env=None):
    """`run(cmd)` under GNU time writing to `times`: (stdout, wall s, CPU s = user + sys, peak KB)."""
    out = run(["/usr/bin/time", "-o", str(times), "-f", TIME_FORMAT] + cmd, env)
    return (out,) + read_times(times)


def read_times(times):
    wall, user, system, rss = times.read_text().split()[-4:]
    return float(wall), float(user) + float(system), int(rss)


def timed_pack(cmd, out, name, env):
    """`cmd`, a `packbench pack … --output OUT/name`, under GNU time with its messages in
    OUT/name.log: (its JSON sidecar, CPU s, peak KB). Exits when it wrote no sidecar."""
    record, times = out / f"{name}.json", out / f"{name}.time.txt"
    record.unlink(missing_ok=True)
    with open(out / f"{name}.log", "w") as log:
        p = subprocess.run(["/usr/bin/time", "-o", str(times), "-f", TIME_FORMAT] + cmd, env=env,
                           stdout=subprocess.DEVNULL, stderr=log)
    if not record.exists():
        sys.exit(f"{' '.join(cmd)} failed (status {p.returncode}); see {name}.log")
    _, cpu, rss = read_times(times)
    return json.loads(record.read_text()), cpu, rss
