"""Read an igms session log into numpy arrays.

    import igmslog
    log = igmslog.read("session.lcmlog")      # also .lcmlog.gz
    log.info.scene_path, log.info.clock       # session_info_t (the first one)
    log.files.robots[k].model_path            # session_files_t: every robot's files (None in older logs)
    igmslog.model_texts(log)                  # {robot: its model file's text}, from the log alone
    log.states["t"], log.states["q"]          # (N,) simulated time, (N, nq)
    log.inputs["tip_position"]                # (M, 3) haptic inputs, by arrival
    log.hands["client"], log.hands["force"]   # (H,), (H, 3): one row per hand per state (several people at once)
    log.contacts["seq"], log.contacts["force"]  # (C,), (C, 3): one row per contact per contacts_t (IGMS_CONTACTS)
    log.client_status[-1].rate_hz             # the decoded status messages, in order
    log.counts, log.undecodable               # events per channel; messages that did not decode

Needs the `lcm` module (PyPI: scripts/setup/python_env.sh puts it in the project's
.venv) and the generated message types (build/python, or the installed igms
package). A .gz log is inflated to a temporary file first: LCM's EventLog reads
plain files only (`zcat X.lcmlog.gz > X.lcmlog` does the same by hand).
"""
import collections
import gzip
import os
import shutil
import tempfile
import zlib

import lcm
import numpy as np

from igms import (client_status_t, contacts_t, haptic_input_t, robot_state_t, server_status_t,
                  session_files_t, session_info_t)

STATE_CHANNELS = ("IGMS_ROBOT_STATE", "IGMS_ROBOT_STATE_TRUTH")
TYPES = {
    "IGMS_SESSION_INFO": session_info_t,
    "IGMS_SESSION_FILES": session_files_t,
    "IGMS_ROBOT_STATE": robot_state_t,
    "IGMS_ROBOT_STATE_TRUTH": robot_state_t,
    "IGMS_HAPTIC_INPUT": haptic_input_t,
    "IGMS_SERVER_STATUS": server_status_t,
    "IGMS_CLIENT_STATUS": client_status_t,
    "IGMS_CONTACTS": contacts_t,
}


class SessionLog:
    def __init__(self):
        self.info = None
        self.files = None
        self.counts = collections.Counter()
        self.undecodable = collections.Counter()
        self.server_status = []
        self.client_status = []
        self.states = {}
        self.inputs = {}
        self.hands = {}
        self.contacts = {}
        self.contact_messages = {}


def events(path):
    """(channel, timestamp_us, data) of every event, in file order."""
    plain, tmp = path, None
    if path.endswith(".gz"):
        fd, tmp = tempfile.mkstemp(suffix=".lcmlog")
        with os.fdopen(fd, "wb") as out, gzip.open(path, "rb") as src:
            shutil.copyfileobj(src, out)
        plain = tmp
    try:
        log = lcm.EventLog(plain, "r")
        for e in log:
            yield e.channel, e.timestamp, e.data
        log.close()
    finally:
        if tmp:
            os.unlink(tmp)


def _decode(kind, data):
    try:
        return kind.decode(data)
    except Exception:  # a damaged message or another version's type: counted, never fatal
        return None


def _columns(messages, fields):
    """{field: array over the messages} for each field."""
    return {f: np.array([getattr(m, f) for m in messages]) for f in fields}


def read(path):
    """The session in `path` as a SessionLog."""
    out = SessionLog()
    raw = collections.defaultdict(list)
    for channel, _, data in events(path):
        out.counts[channel] += 1
        kind = TYPES.get(channel)
        if kind is None:
            continue
        m = _decode(kind, data)
        if m is None:
            out.undecodable[channel] += 1
        else:
            raw[channel].append(m)
    if raw["IGMS_SESSION_INFO"]:
        out.info = raw["IGMS_SESSION_INFO"][0]
        # The files that go with that session info (the same token).
        out.files = next((f for f in raw["IGMS_SESSION_FILES"] if f.session_token == out.info.session_token), None)
    out.server_status = raw["IGMS_SERVER_STATUS"]
    out.client_status = raw["IGMS_CLIENT_STATUS"]
    # The truth channel holds every step in a fault-injected session.
    states = raw["IGMS_ROBOT_STATE_TRUTH"] or raw["IGMS_ROBOT_STATE"]
    states = sorted(states, key=lambda s: s.seq)
    if states:
        out.states = _columns(states, ("seq", "sim_time", "q", "v", "qdd", "tau", "mode", "interaction_force",
                                       "in_collision", "min_obstacle_distance", "step_us"))
        out.states["t"] = out.states["sim_time"]
        out.states["link_positions"] = np.array([[p[:3] for p in s.link_poses] for s in states])
        out.states["interaction_torque"] = np.array([s.interaction_torque for s in states])
        out.states["nhands"] = np.array([s.nhands for s in states])
        rows = [(s.seq, s.sim_time, s.hand_client[h], s.hand_input_seq[h], s.hand_mode[h], s.hand_force[h],
                 s.hand_torque[h], s.hand_point[h]) for s in states for h in range(s.nhands)]
        names = ("seq", "t", "client", "input_seq", "mode", "force", "torque", "point")
        out.hands = {n: np.array([r[i] for r in rows]) for i, n in enumerate(names)}
    contacts = sorted(raw["IGMS_CONTACTS"], key=lambda c: c.seq)
    if contacts:
        out.contact_messages = _columns(contacts, ("seq", "sim_time", "total", "ncontacts", "dropped"))
        rows = [(c.seq, c.sim_time, c.link_a[k], c.link_b[k], c.point[k], c.normal[k], c.force[k], c.distance[k])
                for c in contacts for k in range(c.ncontacts)]
        names = ("seq", "t", "link_a", "link_b", "point", "normal", "force", "distance")
        out.contacts = {n: np.array([r[i] for r in rows]) for i, n in enumerate(names)}
    inputs = raw["IGMS_HAPTIC_INPUT"]
    if inputs:
        out.inputs = _columns(inputs, ("seq", "utime", "mode", "client_id", "tip_position"))
    return out


def model_texts(log):
    """{robot name: its model file's text} from the log alone: every robot's from the session files,
    else (an older log) the first robot's from the session info, under ""."""
    if log.files is not None:
        return {r.robot: zlib.decompress(bytes(r.model_zlib)).decode() for r in log.files.robots
                if r.model_size > 0}
    if log.info is not None and log.info.model_size > 0:
        return {"": zlib.decompress(bytes(log.info.model_zlib)).decode()}
    return {}


def link_names(log):
    """The link order of link_poses (from the server status)."""
    for s in log.server_status:
        if s.link_names:
            return list(s.link_names)
    return []
