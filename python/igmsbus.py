"""Sign messages for a keyed igms bus from Python (docs/signed_bus.md).

    import igmsbus
    key = igmsbus.read_key_file(path)              # the bus key: 64 hex digits, mode 0600
    signer, verifier = igmsbus.Signer(key), igmsbus.Verifier(key)
    lc.publish(channel, signer.sign(channel, msg.encode()))
    payload = verifier.check(channel, data)        # None: refused (counted in verifier.refused)

The trailer after the LCM payload is "IGB1" | sender (16 B) | counter (8 B) |
time (8 B, microseconds) | tag (16 B). The tag is AES-256-GMAC under the
sender's key HMAC-SHA256(bus key, "igms bus v1" | sender), with the counter as
the nonce, over len(channel) (4 B) | channel | payload | the trailer before the
tag. A replay (igms-replay play) signs with "IGR1" and the label "igms bus
replay v1". Readers without the key decode the payload as before. Needs the
`cryptography` package (Debian: python3-cryptography).

The Verifier makes the checks bus/message_verifier.h makes, with the same
bounds, and both languages' tests run the vectors in tests/data/bus_vectors.json.
"""
import errno
import hashlib
import hmac
import os
import stat
import struct
import time
import weakref

from cryptography.hazmat.primitives.ciphers.aead import AESGCM

MAGIC = b"IGB1"
REPLAY_MAGIC = b"IGR1"
TRAILER_BYTES = 4 + 16 + 8 + 8 + 16

# The bounds of bus/message_verifier.h.
MAX_AGE_S = 60.0          # a message signed longer ago (or ahead) is stale
FORGET_S = 2 * MAX_AGE_S  # a sender silent this long may be forgotten: nothing it signed is fresh then
WINDOW = 1024             # counters behind the newest still taken once
MAX_SENDERS = 256
MAX_STREAMS = 2048
REFUSALS = ("unsigned", "bad_signature", "replayed", "too_many_senders", "stale", "replayed_session", "other_sender")


def read_key_file(path):
    """The bus key's 32 bytes; ValueError with one line for a link, a file another user owns or others can
    read, or one that is not a key. Opened once (not following a link) and checked on that descriptor,
    as bus/bus_key.cc does: a name checked and opened again can be swapped between the two."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NOCTTY | os.O_NONBLOCK)
    except OSError as e:
        if e.errno == errno.ELOOP:
            raise ValueError("%s: a symbolic link; give the key file itself" % path) from None
        if e.errno == errno.EACCES:
            raise ValueError("%s: not readable by this user (permission denied)" % path) from None
        raise ValueError("%s: %s" % (path, e.strerror)) from None
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        raise ValueError("%s: not a regular file" % path)
    with os.fdopen(fd, "rb") as f:
        if st.st_uid != os.geteuid():
            raise ValueError("%s: owned by uid %d, not by this user (uid %d)" % (path, st.st_uid, os.geteuid()))
        if st.st_mode & (stat.S_IRWXG | stat.S_IRWXO):
            raise ValueError("%s: readable by others (mode %o); chmod 600 it" % (path, stat.S_IMODE(st.st_mode)))
        text = f.read(4097)
    try:
        key = bytes.fromhex(text.decode("ascii").strip())
    except (ValueError, UnicodeDecodeError):
        key = b""
    if len(key) != 32:
        raise ValueError("%s: not a bus key (64 hex digits)" % path)
    return key


def _gcm(bus_key, sender, replayed=False):
    label = b"igms bus replay v1" if replayed else b"igms bus v1"
    return AESGCM(hmac.new(bus_key, label + sender, hashlib.sha256).digest())


def _tag(gcm, channel, head, counter):
    name = channel.encode()
    nonce = b"\0\0\0\0" + struct.pack(">Q", counter)
    return gcm.encrypt(nonce, b"", struct.pack(">I", len(name)) + name + head)  # GMAC: the tag alone


class Signer:
    """One sender: a random id per Signer, a counter that only grows (never a nonce twice). A forked
    child's Signers draw new ids and count again from the start (signing on as the parent's would
    repeat GMAC nonces under one key)."""

    _live = weakref.WeakSet()

    def __init__(self, bus_key):
        self._bus_key = bus_key
        self._draw()
        Signer._live.add(self)

    def _draw(self):
        self.sender = os.urandom(16)
        self._gcm = _gcm(self._bus_key, self.sender)
        self._counter = 0

    @classmethod
    def _after_fork_in_child(cls):
        for signer in list(cls._live):
            signer._draw()

    def sign(self, channel, payload):
        self._counter += 1
        return sign_as(self._bus_key, self.sender, self._counter, int(time.time() * 1e6), channel, payload,
                       gcm=self._gcm)


def sign_as(bus_key, sender, counter, time_us, channel, payload, replayed=False, gcm=None):
    """A message signed as `sender` with this counter and time (a test's, or a Signer's)."""
    head = payload + (REPLAY_MAGIC if replayed else MAGIC) + sender + struct.pack(">QQ", counter, time_us)
    return head + _tag(gcm or _gcm(bus_key, sender, replayed), channel, head, counter)


os.register_at_fork(after_in_child=Signer._after_fork_in_child)


class Verifier:
    """Takes a message once, signed under the bus key within a minute of now; counts what it refuses by
    reason (`refused`). As bus/message_verifier.h: a counter is new for its sender on its channel when it
    is above the newest or one of the WINDOW before it not seen yet; at most MAX_SENDERS senders and
    MAX_STREAMS (sender, channel) streams, a sender forgotten (its streams too) only after FORGET_S of
    silence, when a new one needs its place; a replay's signature refused unless accept_replays."""

    def __init__(self, bus_key, accept_replays=False):
        self._key = bus_key
        self._accept_replays = accept_replays
        self._senders = {}  # (sender, replayed) -> [AESGCM, heard (monotonic s)]
        self._streams = {}  # ((sender, replayed), channel) -> [newest, set of counters seen within the window]
        self.accepted = 0
        self.refused = {r: 0 for r in REFUSALS}

    def check(self, channel, data):
        return self.check_at(channel, data, int(time.time() * 1e6), time.monotonic())

    def _refuse(self, why):
        self.refused[why] += 1
        return None

    def _forget(self, who):
        del self._senders[who]
        for stream in [s for s in self._streams if s[0] == who]:
            del self._streams[stream]

    def _silent(self, steady_s, but=None):
        return [w for w, (_, heard) in self._senders.items() if w != but and steady_s - heard > FORGET_S]

    def check_at(self, channel, data, now_us, steady_s):
        """The payload, or None (counted): at `now_us` on the signers' wall clock, `steady_s` on a monotonic one."""
        magic = data[-TRAILER_BYTES:-TRAILER_BYTES + 4] if len(data) >= TRAILER_BYTES else b""
        if magic not in (MAGIC, REPLAY_MAGIC):
            return self._refuse("unsigned")
        replayed = magic == REPLAY_MAGIC
        t = len(data) - TRAILER_BYTES
        sender = bytes(data[t + 4:t + 20])
        counter, when = struct.unpack(">QQ", data[t + 20:t + 36])
        who = (sender, replayed)
        known = self._senders.get(who)
        gcm = known[0] if known else _gcm(self._key, sender, replayed)
        if not hmac.compare_digest(_tag(gcm, channel, bytes(data[:-16]), counter), bytes(data[-16:])):
            return self._refuse("bad_signature")
        if replayed and not self._accept_replays:
            return self._refuse("replayed_session")
        if abs(now_us - when) * 1e-6 > MAX_AGE_S:
            return self._refuse("stale")
        if not known:
            if len(self._senders) >= MAX_SENDERS:
                silent = self._silent(steady_s)
                if not silent:
                    return self._refuse("too_many_senders")
                self._forget(min(silent, key=lambda w: self._senders[w][1]))
            self._senders[who] = known = [gcm, steady_s]
        stream = self._streams.get((who, channel))
        if stream is None:
            if len(self._streams) >= MAX_STREAMS:
                for w in self._silent(steady_s, but=who):
                    self._forget(w)
                if len(self._streams) >= MAX_STREAMS:
                    return self._refuse("too_many_senders")
            self._streams[(who, channel)] = [counter, {counter}]
        else:
            newest, seen = stream
            if counter > newest:
                stream[0] = counter
                stream[1] = {c for c in seen if c > counter - WINDOW}
                stream[1].add(counter)
            elif newest - counter >= WINDOW or counter in seen:
                return self._refuse("replayed")
            else:
                seen.add(counter)
        known[1] = steady_s
        self.accepted += 1
        return data[:t]
