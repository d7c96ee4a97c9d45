#!/usr/bin/env python3
"""await_nodes.py [--merge OUT.bag PART.bag...] NODE...

Exits once every NODE has registered with the master and then gone. As a
required node in a launch file it ends the launch when a set of simulators has
finished. With --merge it first merges the simulators' own bags (each node
records its topics in-process) into OUT.bag and removes the parts."""
import os
import sys
import time

import rosbag
import rosnode
import rospy


def merge(out_path, parts):
    count = 0
    with rosbag.Bag(out_path, "w") as out:
        for part in parts:
            with rosbag.Bag(part) as bag:
                for topic, msg, t in bag.read_messages(raw=True):
                    out.write(topic, msg, t, raw=True)
                    count += 1
    for part in parts:
        os.remove(part)
    rospy.loginfo("await_nodes: merged %d messages from %d bags into %s", count, len(parts), out_path)


def main():
    rospy.init_node("await_nodes", anonymous=True)
    args = rospy.myargv(sys.argv)[1:]
    out_bag, parts = None, []
    if args and args[0] == "--merge":
        out_bag = args[1]
        args = args[2:]
        while args and args[0].endswith(".part"):
            parts.append(args.pop(0))
    names = set(args)
    seen = set()
    # A node that never registers (it failed at start-up) must not hang the launch.
    unseen_deadline = time.time() + 60.0
    while not rospy.is_shutdown():
        try:
            alive = set(rosnode.get_node_names())
        except rosnode.ROSNodeIOException:
            alive = set()
        seen |= alive & names
        if seen == names and not (alive & names):
            rospy.loginfo("await_nodes: %s have all exited", " ".join(sorted(names)))
            break
        if seen != names and time.time() > unseen_deadline:
            rospy.logerr("await_nodes: %s never started", " ".join(sorted(names - seen)))
            sys.exit(1)
        time.sleep(0.1)
    if out_bag:
        merge(out_bag, parts)


if __name__ == "__main__":
    main()
