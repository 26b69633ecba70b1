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
tag. Readers without the key decode the payload as before. Needs the
`cryptography` package (Debian: python3-cryptography).
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
TRAILER_BYTES = 4 + 16 + 8 + 8 + 16


MAX_AGE_S = 60.0


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


def _gcm(bus_key, sender):
    return AESGCM(hmac.new(bus_key, b"igms bus v1" + sender, hashlib.sha256).digest())


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
        head = payload + MAGIC + self.sender + struct.pack(">QQ", self._counter, int(time.time() * 1e6))
        return head + _tag(self._gcm, channel, head, self._counter)


os.register_at_fork(after_in_child=Signer._after_fork_in_child)


class Verifier:
    """Takes a message once, signed under the bus key within a minute; counts what it refuses by reason.
    A counter must be above the newest taken from its sender on its channel (no window: for one stream)."""

    def __init__(self, bus_key):
        self._key = bus_key
        self._senders = {}  # sender -> AESGCM
        self._newest = {}   # (sender, channel) -> counter
        self.accepted = 0
        self.refused = {"unsigned": 0, "bad_signature": 0, "replayed": 0, "stale": 0}

    def check(self, channel, data):
        if len(data) < TRAILER_BYTES or data[-TRAILER_BYTES:-TRAILER_BYTES + 4] != MAGIC:
            self.refused["unsigned"] += 1
            return None
        t = len(data) - TRAILER_BYTES
        sender = data[t + 4:t + 20]
        counter, when = struct.unpack(">QQ", data[t + 20:t + 36])
        if sender not in self._senders:
            if len(self._senders) > 256:
                self._senders.clear()
            self._senders[sender] = _gcm(self._key, sender)
        if not hmac.compare_digest(_tag(self._senders[sender], channel, data[:-16], counter), data[-16:]):
            self.refused["bad_signature"] += 1
            return None
        if abs(time.time() - when * 1e-6) > MAX_AGE_S:
            self.refused["stale"] += 1
            return None
        if counter <= self._newest.get((sender, channel), 0):
            self.refused["replayed"] += 1
            return None
        self._newest[(sender, channel)] = counter
        self.accepted += 1
        return data[:t]
