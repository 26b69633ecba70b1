"""Bad readings for a bus device (lcm_device_test): what a broken or hostile
sender puts on IGMS_DEVICE_READING while a good device runs. With the bus key
it signs NaN, out-of-range and out-of-order readings and undecodable bytes
(the client, pinned to the good device's sender, refuses them as
other_sender); without it, unsigned readings and
readings signed under another key (refused by the message check).
    bad_device_readings.py URL KEY_FILE SECONDS STATS_JSON"""
import json
import math
import os
import sys
import time

import lcm

import igmsbus
from igms import device_reading_t

url, key_file, seconds, stats_path = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
lc = lcm.LCM(url)
channel = "IGMS_DEVICE_READING"
signer = igmsbus.Signer(igmsbus.read_key_file(key_file))
stranger = igmsbus.Signer(os.urandom(32))
sent = {"nan": 0, "out_of_range": 0, "out_of_order": 0, "undecodable": 0, "unsigned": 0, "other_key": 0}


def reading(seq, position):
    m = device_reading_t()
    m.utime, m.seq = int(time.time() * 1e6), seq
    m.position, m.velocity = position, [0.0, 0.0, 0.0]
    m.orientation = [1.0, 0.0, 0.0, 0.0]
    return m.encode()


time.sleep(1.0)  # beside a device the client has taken: its first reading (and limits) is the good device's
end = time.time() + seconds - 1.0
while time.time() < end:
    big = 10**12  # a seq above the good device's: only the values can refuse it
    lc.publish(channel, signer.sign(channel, reading(big, [math.nan, 0.0, 0.0])))
    sent["nan"] += 1
    lc.publish(channel, signer.sign(channel, reading(big, [5.0, 0.0, 0.0])))
    sent["out_of_range"] += 1
    lc.publish(channel, signer.sign(channel, reading(1, [0.0, 0.0, 0.0])))
    sent["out_of_order"] += 1
    lc.publish(channel, signer.sign(channel, os.urandom(40)))
    sent["undecodable"] += 1
    lc.publish(channel, reading(big, [0.05, 0.05, 0.05]))
    sent["unsigned"] += 1
    lc.publish(channel, stranger.sign(channel, reading(big, [0.05, 0.05, 0.05])))
    sent["other_key"] += 1
    time.sleep(0.005)
json.dump(sent, open(stats_path, "w"))
