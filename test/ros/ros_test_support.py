"""Shared helpers of the node's rostests: collectors synchronised on
received messages (threading conditions with a timeout), the headless runner's
reference output, and the scene file."""
import json
import os
import subprocess
import tempfile
import threading
import time

import roslib.packages
import rospkg
import rospy

# Wall-clock bound for a wait on messages: the paper scene at real_time_factor 0
# takes well under a second; the bound only turns a hang into a failure.
WAIT_TIMEOUT_S = 60.0

PKG = "rotor_rub_sim"
PAPER_SCENE = os.path.join(rospkg.RosPack().get_path(PKG), "config", "paper_runup.yaml")


def find_binary(name):
    paths = roslib.packages.find_node(PKG, name)
    if not paths:
        raise RuntimeError("cannot find %s in package %s" % (name, PKG))
    return paths[0]


def run_runner(extra_args, prefix):
    """Runs rotor_rub_run on the paper scene; returns its JSON summary."""
    subprocess.run([find_binary("rotor_rub_run"), "--scene", PAPER_SCENE, "--csv", prefix + ".csv",
                    "--summary", prefix + ".json", "--quiet"] + extra_args, check=True)
    with open(prefix + ".json") as f:
        return json.load(f)


class Collector(object):
    """Collects every message of a topic; wait_for() blocks on a predicate."""

    def __init__(self, topic, msg_type):
        self.msgs = []
        self.arrival_times = []  # time.monotonic() at each message's delivery
        self.cond = threading.Condition()
        # queue_size None: unbounded, so a burst at real_time_factor 0 is not dropped.
        self.sub = rospy.Subscriber(topic, msg_type, self._cb, queue_size=None)

    def _cb(self, msg):
        with self.cond:
            self.msgs.append(msg)
            self.arrival_times.append(time.monotonic())
            self.cond.notify_all()

    def clear(self):
        with self.cond:
            self.msgs = []
            self.arrival_times = []

    def wait_for(self, predicate, what):
        with self.cond:
            ok = self.cond.wait_for(lambda: predicate(self.msgs), timeout=WAIT_TIMEOUT_S)
        if not ok:
            raise AssertionError("timed out after %g s waiting for %s (%d messages so far)" %
                                 (WAIT_TIMEOUT_S, what, len(self.msgs)))
        return list(self.msgs)

    def wait_connected(self):
        """Until the publisher side has connected to us."""
        import time
        deadline = time.time() + WAIT_TIMEOUT_S
        while self.sub.get_num_connections() == 0:
            if time.time() > deadline:
                raise AssertionError("no publisher connected to %s" % self.sub.name)
            rospy.sleep(0.01)


def temp_prefix(name):
    return os.path.join(tempfile.mkdtemp(prefix="rotor_rub_test_"), name)


# The simulator's end stops closed_loop.launch, the rub monitor with it: on a
# loaded machine the monitor's last verdict (the one the tests wait for) needs
# more than the default second to come out. Not on the tests' wall time: they
# run four at a time beside the package and docs checks (scripts/run_tests.sh).
MONITOR_LINGER = "exit_linger_s:=5"


def launch_monitored(args, ns, listeners, before_resume=lambda: None):
    """closed_loop.launch with start_paused, resumed only once every listener
    (a Collector) has connected, so none misses the run's first messages (a
    latched topic gives a late subscriber only its last one); before_resume()
    runs while the node waits (faults injected there land at their stamps).
    A launch that fails fails the caller. Returns the launch's output (the
    simulator's and the monitor's logs)."""
    from rotor_rub_msgs.msg import SolverStats
    from std_srvs.srv import Trigger
    stats = Collector("/%s/solver_stats" % ns, SolverStats)
    proc = subprocess.Popen([find_binary("launch_checked.py"), "rotor_rub_sim", "closed_loop.launch",
                             "start_paused:=true", "ns:=" + ns, MONITOR_LINGER] + list(args), stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    try:
        stats.wait_for(lambda ms: any(m.status == SolverStats.PAUSED for m in ms), "the node paused at start")
        for c in listeners:
            c.wait_connected()
        before_resume()
        rospy.ServiceProxy("/%s/resume" % ns, Trigger)()
        out, _ = proc.communicate(timeout=600)
        assert proc.returncode == 0, out[-3000:]
        return out
    finally:
        if proc.poll() is None:
            proc.kill()
        stats.sub.unregister()


def wait_last_verdict(alarms, end_s, launch_output):
    """The monitor's verdicts up to the one stamped at the run's end (within
    a 0.1 s verdict period); on a timeout, the failure carries the launch's
    log (the monitor's errors, which streams it heard)."""
    try:
        return alarms.wait_for(lambda ms: ms and ms[-1].header.stamp.to_sec() >= end_s - 0.1,
                               "the monitor's last verdict")
    except AssertionError as e:
        raise AssertionError("%s; the launch's output, its end:\n%s" % (e, launch_output[-4000:])) from None
