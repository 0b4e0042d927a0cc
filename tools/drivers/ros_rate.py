# SPDX-License-Identifier: BSD-3-Clause
"""Counts the messages of one ROS 1 topic, whatever their type: from the
first message on, for SECONDS. Prints JSON: count, rate_hz, interval_ms
(p50, p95, max). Run with Debian's python3 (rospy), by run_driver.py.

usage: ros_rate.py TOPIC SECONDS FIRST_TIMEOUT
"""
import json
import sys
import threading
import time

import rospy


def percentile(values, fraction):
    ordered = sorted(values)
    if not ordered:
        return None
    return round(ordered[min(len(ordered) - 1, int(fraction * len(ordered)))], 3)


def main():
    topic, seconds, first_timeout = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
    stamps = []
    first = threading.Event()

    def on_message(_message):
        stamps.append(time.monotonic())
        first.set()

    rospy.init_node("wsgsim_rate", anonymous=True, disable_signals=True)
    subscriber = rospy.Subscriber(topic, rospy.AnyMsg, on_message, queue_size=10000)
    if not first.wait(first_timeout):
        print(json.dumps({"count": 0, "error": "no message on %s within %g s"
                          % (topic, first_timeout)}))
        return
    time.sleep(seconds)
    subscriber.unregister()
    window = [t for t in stamps if t - stamps[0] <= seconds]
    intervals = [(b - a) * 1000.0 for a, b in zip(window, window[1:])]
    span = window[-1] - window[0] if len(window) > 1 else 0.0
    print(json.dumps({
        "count": len(window),
        "rate_hz": round((len(window) - 1) / span, 2) if span else 0.0,
        "interval_ms": {"p50": percentile(intervals, 0.5), "p95": percentile(intervals, 0.95),
                        "max": round(max(intervals), 3) if intervals else None},
    }))


if __name__ == "__main__":
    main()
