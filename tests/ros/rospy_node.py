"""A rospy node for the tests (run by Debian's /usr/bin/python3, where rospy lives; not a test module).

    /usr/bin/python3 rospy_node.py '{"name": "lidar", "publish": [{"topic": "/scan", "rate": 10, "bytes": 1000}],
                                     "subscribe": ["/cmd"]}'

Each publication sends ``std_msgs/String`` messages whose serialized size is ``bytes`` (4 bytes of length, then
``bytes - 4`` characters; a ``seq:<n>;`` prefix numbers them), or with ``"type": "float64"`` ``std_msgs/Float64``
messages whose value is the sequence number 0, 1, 2, ..., at ``rate`` messages per second, on a ``rospy.Timer``
per topic. It prints ``ready`` once every publisher and subscriber is registered with the
master, and runs until it is terminated. ``"burn": f`` keeps a thread busy for a share ``f`` of the time.
"""

import json
import sys
import threading
import time

import rospy
from std_msgs.msg import Float64, String


def main() -> None:
    spec = json.loads(sys.argv[1])
    rospy.init_node(spec["name"], anonymous=False, disable_signals=False)
    for topic in spec.get("subscribe", []):
        # AnyMsg: a subscriber of any type, as a node that only forwards would be
        rospy.Subscriber(topic, rospy.AnyMsg, lambda _msg: None, queue_size=100)
    timers = []
    for pub in spec.get("publish", []):
        numeric = pub.get("type") == "float64"
        publisher = rospy.Publisher(pub["topic"], Float64 if numeric else String, queue_size=100, latch=False)
        body = max(0, int(pub.get("bytes", 8)) - 4)
        state = {"n": 0}

        def send(_event, publisher=publisher, body=body, state=state, numeric=numeric):
            if numeric:
                publisher.publish(Float64(data=float(state["n"])))
            else:
                head = f"seq:{state['n']};"
                publisher.publish(String(data=(head + "x" * body)[:body] if body >= len(head) else "x" * body))
            state["n"] += 1

        timers.append(rospy.Timer(rospy.Duration(1.0 / float(pub["rate"])), send))
    if spec.get("burn"):  # a CPU load: busy for `burn` of every 20 ms
        busy = 0.02 * float(spec["burn"])

        def burn():
            while True:
                until = time.monotonic() + busy
                while time.monotonic() < until:
                    pass
                time.sleep(0.02 - busy)

        threading.Thread(target=burn, daemon=True).start()
    print("ready", flush=True)
    rospy.spin()


if __name__ == "__main__":
    main()
