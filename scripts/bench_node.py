#!/usr/bin/env python3
"""The node's performance benchmark (issue 3): the paper scene at a 10 kHz
state rate, real_time_factor 0, recording a bag through sim.launch. Prints
the achieved real-time factor, the messages lost (published - recorded) and
the ROS layer's cost against the headless runner on the same scene and rate,
measured in the same run (ratios: the machine is noisy).

Each repeat also runs the node without recording, so that the recording's
own cost shows as a ratio measured in the same run. With --page, the medians
of each rate are also written into docs/benchmarks.md between
<!-- BEGIN GENERATED: node --> and <!-- END GENERATED: node -->, with the
date, the machine and the command.

usage: scripts/bench_node.sh [--rate HZ [HZ ...]] [--repeats N] [--method M] [--page docs/benchmarks.md]"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import rosbag

from doc_blocks import block, machine, now_utc, write_block

p = argparse.ArgumentParser()
p.add_argument("--rate", type=float, nargs="+", default=[10000.0], help="state rates [Hz], each measured in turn")
p.add_argument("--repeats", type=int, default=3)
p.add_argument("--method", default="switching")
p.add_argument("--runner", required=True)
p.add_argument("--scene", required=True)
p.add_argument("--page", help="also write the medians into this page's node block (docs/benchmarks.md)")
a = p.parse_args()
if a.page:  # before minutes of measuring
    try:
        block(open(a.page).read(), "node")
    except (OSError, ValueError) as e:
        sys.exit("bench_node: %s: %s" % (a.page, e))

tmp = tempfile.mkdtemp(prefix="rotor_rub_bench_")


def measure(rate):
    """The repeats at one state rate, one dict per repeat."""
    params = os.path.join(tmp, "params.yaml")
    with open(params, "w") as f:
        f.write("output_rate_hz: %r\nexit_linger_s: 0.0\n" % rate)
    rows = []
    for r in range(a.repeats):
        # Headless: the core alone, no output written (integration + sampling).
        t0 = time.monotonic()
        subprocess.run([a.runner, "--scene", a.scene, "--method", a.method, "--rate", str(rate), "--quiet",
                        "--summary", os.path.join(tmp, "runner.json")], check=True)
        runner_process_s = time.monotonic() - t0
        with open(os.path.join(tmp, "runner.json")) as f:
            runner_wall_s = json.load(f)["stats"]["wall_time_s"]
        bag = os.path.join(tmp, "bench_%d.bag" % r)
        subprocess.run(["roslaunch", "rotor_rub_sim", "sim.launch", "record:=true", "bag:=" + bag,
                        "real_time_factor:=0", "method:=" + a.method, "scene:=" + a.scene, "params:=" + params],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        # The same without recording: the node logs its achieved real-time factor on finishing.
        out = subprocess.run(["roslaunch", "rotor_rub_sim", "sim.launch", "record:=false", "real_time_factor:=0",
                              "method:=" + a.method, "scene:=" + a.scene, "params:=" + params],
                             check=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True).stdout
        found = re.findall(r"achieved real-time factor ([0-9.]+)", out)
        if not found:
            raise SystemExit("bench_node: the node without recording did not report its real-time factor:\n" + out)
        with rosbag.Bag(bag) as b:
            recorded = b.get_message_count(topic_filters=["/rotor_rub_sim/state"])
            stats = [m for _, m, _ in b.read_messages(topics=["/rotor_rub_sim/solver_stats"])][-1]
        rows.append(dict(rtf=stats.real_time_factor, rtf_no_record=float(found[-1]), node_wall=stats.wall_time,
                         sim=stats.sim_time, published=stats.states_published, recorded=recorded,
                         lost=stats.states_published - recorded, runner_wall=runner_wall_s,
                         runner_process=runner_process_s, bag_mb=os.path.getsize(bag) / 1e6,
                         integrator=stats.integrator))
    return rows


page_rows = []
for rate in a.rate:
    rows = measure(rate)
    print("paper scene (%s), method %s on %s, state rate %g Hz, real_time_factor 0, recording a bag; %d repeats, "
          "%d cores" % (os.path.basename(a.scene), a.method, rows[0]["integrator"], rate, a.repeats, os.cpu_count()))
    print("%-7s %10s %14s %10s %10s %6s %12s %12s %10s %8s" % (
        "repeat", "RTF", "RTF no record", "published", "recorded", "lost", "node wall s", "runner s", "ROS/core",
        "bag MB"))
    for i, r in enumerate(rows):
        print("%-7d %10.1f %14.1f %10d %10d %6d %12.3f %12.4f %10.1f %8.1f" % (
            i, r["rtf"], r["rtf_no_record"], r["published"], r["recorded"], r["lost"], r["node_wall"],
            r["runner_wall"], r["node_wall"] / r["runner_wall"], r["bag_mb"]))
    med = lambda k: statistics.median(r[k] for r in rows)  # noqa: E731
    print("median: real-time factor %.1f (target >= 50), lost %d (target 0), node wall %.3f s = %.1f x the "
          "headless core's %.4f s" % (med("rtf"), max(r["lost"] for r in rows), med("node_wall"),
                                     med("node_wall") / med("runner_wall"), med("runner_wall")))
    print("without recording: real-time factor %.1f; recording costs %.2f x the node's wall time"
          % (med("rtf_no_record"), med("rtf_no_record") / med("rtf")))
    page_rows.append("| %g Hz | %.0f | %.0f | %d / %d / %d | %.3f s | %.1fx | %.1f MB |" % (
        rate, med("rtf"), med("rtf_no_record"), med("published"), med("recorded"), max(r["lost"] for r in rows),
        med("node_wall"), med("node_wall") / med("runner_wall"), med("bag_mb")))

if a.page:
    command = "scripts/bench_node.sh --repeats %d --method %s --rate %s --page docs/benchmarks.md" % (
        a.repeats, a.method, " ".join("%g" % r for r in a.rate))
    block = ["Written by `scripts/bench_node.py` on %s UTC, on %s (method %s on %s; medians of %d repeats):" % (
        now_utc(), machine(), a.method, rows[0]["integrator"], a.repeats), "", "    " + command, "",
        "| state rate | real-time factor, recording | without recording | states published / recorded / lost "
        "| node wall | ROS/core | bag |", "|---|---|---|---|---|---|---|"] + page_rows
    write_block(a.page, "node", block, "bench_node")
