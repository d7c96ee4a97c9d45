#!/usr/bin/env python3
"""launch_checked.py PKG FILE.launch [arg:=value]...

roslaunch that tells whoever launched how its nodes ended. roslaunch itself
exits 0 when a node fails (and prints a red "REQUIRED process ... has died!"
banner when a required node ends normally). This wrapper runs roslaunch,
passes its output through, and:
  * exits with the first non-zero exit status of a node (and ends the launch
    at once: the other nodes would only wait for the failed one);
  * exits 0 when every node that ended did so with status 0, and replaces the
    banner of a required node's normal end by one plain line.
Interrupted (Ctrl-C), it stops roslaunch and exits 130."""
import re
import signal
import subprocess
import sys

# The "[name-N] " prefix may land on another line (a node's own output can
# interleave); the node's name is also in its command line.
DIED = re.compile(r"process has died \[pid \d+, exit code (-?\d+)(?:.*__name:=(\S+))?")
FINISHED = re.compile(r"\[([^\]]+)\] process has finished cleanly")
BANNER = re.compile(r"REQUIRED process \[([^\]]+)\] has died!|^Initiating shutdown!|^={10,}")


def main(argv):
    if len(argv) < 2 or argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if argv[:1] in (["-h"], ["--help"]) else 2
    proc = subprocess.Popen(["roslaunch"] + argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            bufsize=1)
    status = 0
    failed_node = None
    try:
        for line in proc.stdout:
            plain = re.sub(r"\x1b\[[0-9;]*m", "", line)
            died = DIED.search(plain)
            if died and int(died.group(1)) != 0 and status == 0:
                failed_node, status = died.group(2) or "?", int(died.group(1))
                sys.stdout.write(line)
                sys.stdout.flush()
                proc.send_signal(signal.SIGINT)  # fail fast: end the launch now
                continue
            if status == 0 and BANNER.search(plain.strip()):
                continue  # a required node's normal end is not a crash
            finished = FINISHED.search(plain)
            if finished and status == 0:
                sys.stdout.write("[launch_checked] %s ended with status 0\n" % finished.group(1))
                continue
            sys.stdout.write(line)
            sys.stdout.flush()
        proc.wait()
    except KeyboardInterrupt:
        proc.send_signal(signal.SIGINT)
        proc.wait()
        return 130
    if failed_node is not None:
        sys.stderr.write("launch_checked: node %s exited with status %d\n" % (failed_node, status))
        return status if 0 < status < 256 else 1
    if proc.returncode != 0:
        sys.stderr.write("launch_checked: roslaunch exited with status %d\n" % proc.returncode)
        return proc.returncode
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
