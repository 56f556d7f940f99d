#!/usr/bin/python3
"""Send one protocol to test_protocol_node's run_test action and wait.

    run_test_client.py PROTOCOL.yaml [--out DIR] [--timeout SECONDS]

Prints the feedback (stage, eps_a, q, p, e, I_mom) about once a second and
the result as JSON on the last stdout line. Exit codes: 0 completed,
1 any other verdict, 2 bad arguments or no rig, 130 interrupted (the goal is
cancelled first, so the test stops cleanly and reports "preempted").
"""
import argparse
import json
import os
import sys
import time

import actionlib
import rospy
from virtual_triaxial.msg import RunTestAction, RunTestGoal


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("protocol", help="YAML protocol file (config/protocols/)")
    ap.add_argument("--out", default="", help="output folder (default: the node's ~output_dir)")
    ap.add_argument("--timeout", type=float, default=0.0, help="give up after this many wall seconds (0: never)")
    ap.add_argument("--server-timeout", type=float, default=30.0, help="wait this long for the action server")
    args = ap.parse_args(rospy.myargv()[1:])
    if not os.path.isfile(args.protocol):
        print("run_test_client: protocol: no such file: %s" % args.protocol, file=sys.stderr)
        return 2
    # Wall-clock time for this client: it only waits, and with use_sim_time it
    # would otherwise deserialize every /clock message of the rig in Python
    # (~10 % of a core at 1000 ticks/s).
    rospy.init_node("run_test_client", anonymous=True, disable_signals=True, disable_rostime=True)
    rospy.rostime.set_rostime_initialized(True)
    client = actionlib.SimpleActionClient("run_test", RunTestAction)
    if not client.wait_for_server(rospy.Duration(args.server_timeout)):
        print("run_test_client: no run_test action server within %.0f s" % args.server_timeout, file=sys.stderr)
        return 2
    last = [0.0]

    def on_feedback(fb):
        now = time.monotonic()
        if now - last[0] >= 1.0:
            last[0] = now
            print("[%s] eps_a %6.3f %%  q %8.1f kPa  p %8.1f kPa  e %.4f  I_mom %.2e" %
                  (fb.stage, 100 * fb.eps_a, fb.q / 1e3, fb.p / 1e3, fb.e, fb.moment_index), flush=True)

    goal = RunTestGoal(protocol_file=os.path.abspath(args.protocol),
                       output_dir=os.path.abspath(args.out) if args.out else "")
    client.send_goal(goal, feedback_cb=on_feedback)
    t0 = time.monotonic()
    try:
        while not client.wait_for_result(rospy.Duration(0.2)):
            if args.timeout > 0 and time.monotonic() - t0 > args.timeout:
                print("run_test_client: timeout after %.0f s; cancelling" % args.timeout, file=sys.stderr)
                client.cancel_goal()
                client.wait_for_result(rospy.Duration(30.0))
                break
    except KeyboardInterrupt:
        client.cancel_goal()
        client.wait_for_result(rospy.Duration(30.0))
        print(json.dumps(result_dict(client.get_result())))
        return 130
    r = client.get_result()
    if r is None:
        print("run_test_client: no result", file=sys.stderr)
        return 1
    print(json.dumps(result_dict(r)))
    return 0 if r.verdict == "completed" else 1


def result_dict(r):
    if r is None:
        return {}
    keys = ["verdict", "message", "stages", "stop_reasons", "e0", "phi_peak", "eps_peak", "phi_end",
            "mean_moment_index", "max_moment_index", "rate_strategy", "strain_rate_dimensionless_min",
            "strain_rate_dimensionless_max", "quasi_static_threshold", "quasi_static", "runtime", "steps", "ticks",
            "results_file", "summary_file"]
    return {k: (list(getattr(r, k)) if isinstance(getattr(r, k), (list, tuple)) else getattr(r, k)) for k in keys}


if __name__ == "__main__":
    sys.exit(main())
