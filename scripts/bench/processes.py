"""Processes a bench starts: stopped newest first, SIGTERM then (after 10 s) SIGKILL, each waited for."""
import signal
import subprocess
import time


def stop_all(procs, pause=0.0):
    """Stops procs newest first; pause: seconds between two (a logger that must hear the server's end)."""
    for p in reversed(procs):
        p.send_signal(signal.SIGTERM)
        try:
            p.wait(10)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()
        if pause:
            time.sleep(pause)
