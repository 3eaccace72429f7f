"""Long calls release the GIL and stop on Ctrl-C."""

import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

import strider

LONG = {
    "run": "strider.run('random:cluttered', episodes=100000, body='disc', seed=1)",
    # An agent held still in a world with a day's time limit: 1.7 million steps.
    "step": "sim = strider.Simulation(world, body='disc'); sim.drive(0.0, 0.0); sim.step(10**8)",
}


@pytest.mark.parametrize("call", LONG, ids=list(LONG))
def test_ctrl_c_stops_a_long_call(call, tmp_path):
    world = tmp_path / "still.txt"
    world.write_text("start 0 0 0\ngoal 10 0\ntime_limit 86400\n")
    code = textwrap.dedent(
        f"""
        import signal, sys, strider
        # Python's own Ctrl-C handler, whatever this process inherited (a shell's background
        # jobs start with SIGINT ignored).
        signal.signal(signal.SIGINT, signal.default_int_handler)
        world = {str(world)!r}
        print('ready', flush=True)
        try:
            {LONG[call]}
        except KeyboardInterrupt:
            print('interrupted', flush=True)
            sys.exit(3)
        """
    )
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "ready"
        time.sleep(1.0)
        p.send_signal(signal.SIGINT)
        start = time.monotonic()
        out, err = p.communicate(timeout=60)
    finally:
        # A child that did not stop is not left running.
        if p.poll() is None:
            p.kill()
            p.communicate()
    assert p.returncode == 3, err
    assert "interrupted" in out
    assert time.monotonic() - start < 30


def test_runs_release_the_gil():
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    before = len(ticks)
    strider.run("random:cluttered", episodes=16, body="disc", seed=2, threads=1)
    during = len(ticks) - before
    stop.set()
    t.join()
    assert during > 10
