#!/usr/bin/python3
"""Send one protocol to test_protocol_node's run_test action and wait.

    run_test_client.py PROTOCOL.yaml [--out DIR] [--timeout S] [--server-timeout S]
                       [--liveness-timeout S] [--cancel-timeout S]
    run_test_client.py --resume CHECKPOINT.h5 --out DIR [...]

--resume continues a killed test from its checkpoint (DIR/results.h5.checkpoint.h5;
the protocol it names must be unchanged) into DIR's results.h5.

Prints the feedback (stage, eps_a, q, p, e, I_mom) about once a second and
the result as JSON on the last stdout line.

It never waits without a bound: once a second it asks the process that
serves the action (found through the master) for its pid over XML-RPC; a
refused connection or no answer within --liveness-timeout seconds (default
3) means the server died or stopped, and the client gives up naming it.
The first SIGINT (Ctrl-C) cancels the goal and waits at most
--cancel-timeout seconds (default 8) for the "preempted" result; a second
SIGINT ends the client at once.

Exit codes: 0 completed, 1 any other verdict, 2 bad arguments or no rig,
3 the action server died or stopped answering (verdict "interrupted" on the
last line, naming it), 130 interrupted by SIGINT (the goal cancelled first,
so the test stops cleanly and reports "preempted").
"""
import argparse
import json
import os
import signal
import socket
import sys
import time
import xmlrpc.client

import actionlib
import rosgraph
import rospy
from virtual_triaxial.msg import RunTestAction, RunTestGoal

EXIT_SERVER_DIED = 3


class _TimeoutTransport(xmlrpc.client.Transport):
    """XML-RPC over HTTP with a socket timeout (a stopped process never answers)."""

    def __init__(self, timeout):
        super().__init__()
        self._timeout = timeout

    def make_connection(self, host):
        conn = super().make_connection(host)
        conn.timeout = self._timeout
        return conn


class ServerWatch:
    """Liveness of the process serving the run_test action."""

    def __init__(self, action_ns, timeout):
        self.timeout = timeout
        self.node, self.uri, self.pid = "", "", None
        master = rosgraph.Master("/run_test_client")
        topic = rospy.resolve_name(action_ns) + "/status"
        for t, nodes in master.getSystemState()[0]:
            if t == topic and nodes:
                self.node = nodes[0]
        if self.node:
            self.uri = master.lookupNode(self.node)
            self.pid = self._ask()

    def _ask(self):
        proxy = xmlrpc.client.ServerProxy(self.uri, transport=_TimeoutTransport(self.timeout))
        code, _, pid = proxy.getPid("/run_test_client")
        return pid if code == 1 else None

    def dead(self):
        """'' while the server answers, else why it is considered dead."""
        if not self.uri:
            return ""
        try:
            self._ask()
            return ""
        except ConnectionRefusedError:
            return "%s (pid %s) died: its XML-RPC port %s refuses connections" % (self.node, self.pid, self.uri)
        except (socket.timeout, TimeoutError):
            return "%s (pid %s) stopped answering: no XML-RPC answer within %.0f s" % (
                self.node, self.pid, self.timeout)
        except (OSError, xmlrpc.client.Error) as e:
            return "%s (pid %s) unreachable: %s" % (self.node, self.pid, e)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("protocol", nargs="?", default="", help="YAML protocol file (config/protocols/)")
    ap.add_argument("--resume", default="", metavar="CHECKPOINT",
                    help="continue a killed test from this checkpoint (instead of a protocol)")
    ap.add_argument("--out", default="", help="output folder (default: the node's ~output_dir)")
    ap.add_argument("--timeout", type=float, default=0.0, help="give up after this many wall seconds (0: never)")
    ap.add_argument("--server-timeout", type=float, default=30.0, help="wait this long for the action server")
    ap.add_argument("--liveness-timeout", type=float, default=3.0,
                    help="the server is dead when its process does not answer within this many seconds")
    ap.add_argument("--cancel-timeout", type=float, default=8.0,
                    help="after Ctrl-C, wait this long for the preempted result")
    args = ap.parse_args(rospy.myargv()[1:])
    for name in ("timeout", "server_timeout", "liveness_timeout", "cancel_timeout"):
        if not getattr(args, name) >= 0:
            print("run_test_client: --%s: must be >= 0" % name.replace("_", "-"), file=sys.stderr)
            return 2
    if bool(args.protocol) == bool(args.resume):
        print("run_test_client: give exactly one of PROTOCOL.yaml and --resume CHECKPOINT", file=sys.stderr)
        return 2
    if args.resume and not os.path.isfile(args.resume):
        print("run_test_client: --resume: no such file: %s" % args.resume, file=sys.stderr)
        return 2
    if args.protocol and not os.path.isfile(args.protocol):
        print("run_test_client: protocol: no such file: %s" % args.protocol, file=sys.stderr)
        return 2
    # A parent that runs us in the background may have set SIGINT to "ignore";
    # Ctrl-C (or the entry script forwarding it) must reach us.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        return run(args)
    except KeyboardInterrupt:  # a second SIGINT, or one before the goal was sent
        print("run_test_client: interrupted", file=sys.stderr)
        return 130


def run(args):
    # Wall-clock time for this client: it only waits, and with use_sim_time it
    # would otherwise deserialize every /clock message of the rig in Python
    # (~10 % of a core at 1000 ticks/s).
    rospy.init_node("run_test_client", anonymous=True, disable_signals=True, disable_rostime=True)
    rospy.rostime.set_rostime_initialized(True)
    client = actionlib.SimpleActionClient("run_test", RunTestAction)
    if not client.wait_for_server(rospy.Duration(args.server_timeout)):
        print("run_test_client: no run_test action server within %.0f s" % args.server_timeout, file=sys.stderr)
        return 2
    try:
        watch = ServerWatch("run_test", args.liveness_timeout)
    except (OSError, xmlrpc.client.Error, rosgraph.MasterException) as e:
        print("run_test_client: cannot find the run_test server's process: %s" % e, file=sys.stderr)
        return 2
    last = [0.0]

    def on_feedback(fb):
        now = time.monotonic()
        if now - last[0] >= 1.0:
            last[0] = now
            print("[%s] eps_a %6.3f %%  q %8.1f kPa  p %8.1f kPa  e %.4f  I_mom %.2e" %
                  (fb.stage, 100 * fb.eps_a, fb.q / 1e3, fb.p / 1e3, fb.e, fb.moment_index), flush=True)

    goal = RunTestGoal(protocol_file=os.path.abspath(args.protocol) if args.protocol else "",
                       resume=os.path.abspath(args.resume) if args.resume else "",
                       output_dir=os.path.abspath(args.out) if args.out else "")
    client.send_goal(goal, feedback_cb=on_feedback)
    t0 = time.monotonic()
    cancelled = None  # why the goal was cancelled, once it is

    def wait(deadline):
        """True once the result is in; the server's death ends it with a message."""
        t_check = time.monotonic()
        while not client.wait_for_result(rospy.Duration(0.2)):
            now = time.monotonic()
            if deadline is not None and now > deadline:
                return False
            if now - t_check >= 1.0:
                t_check = now
                why = watch.dead()
                if why:
                    raise ServerDied(why)
        return True

    try:
        try:
            while not wait(t0 + args.timeout if args.timeout > 0 else None):
                print("run_test_client: timeout after %.0f s; cancelling" % args.timeout, file=sys.stderr)
                cancelled = "timeout"
                client.cancel_goal()
                wait(time.monotonic() + args.cancel_timeout)
                break
        except KeyboardInterrupt:
            print("run_test_client: interrupted; cancelling the goal (again to quit at once)", file=sys.stderr)
            cancelled = "interrupt"
            client.cancel_goal()
            if not wait(time.monotonic() + args.cancel_timeout):
                print("run_test_client: no result %.0f s after cancelling" % args.cancel_timeout, file=sys.stderr)
    except ServerDied as e:
        why = "the run_test action server " + str(e)
        print("run_test_client: " + why, file=sys.stderr)
        print(json.dumps({"verdict": "interrupted", "message": why}))
        return EXIT_SERVER_DIED
    r = client.get_result()
    if cancelled == "interrupt":
        print(json.dumps(result_dict(r)))
        return 130
    if r is None:
        print("run_test_client: no result", file=sys.stderr)
        return 1
    print(json.dumps(result_dict(r)))
    return 0 if r.verdict == "completed" else 1


class ServerDied(Exception):
    pass


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
