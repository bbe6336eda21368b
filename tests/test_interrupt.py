"""``objsearch.interrupt.stop_on_interrupt``: Ctrl-C during a long run sets a flag instead of
raising, and the handler that was there before comes back afterwards."""

import os
import signal
import threading
import time

import pytest

from objsearch.interrupt import stop_on_interrupt


def send_sigint():
    """SIGINT to this process, as Ctrl-C sends it; Python runs the handler in the main
    thread at the next bytecode, so give it a moment."""
    os.kill(os.getpid(), signal.SIGINT)
    time.sleep(0.01)


@pytest.fixture
def recording_handler():
    """A SIGINT handler that records its calls, installed for the test (the old one is put back)."""
    calls = []
    before = signal.signal(signal.SIGINT, lambda signum, frame: calls.append(signum))
    try:
        yield calls
    finally:
        signal.signal(signal.SIGINT, before)


def test_sigint_in_the_block_sets_the_flag_instead_of_raising(recording_handler):
    with stop_on_interrupt() as stop:
        assert not stop.is_set()
        steps = 0
        while not stop.is_set() and steps < 100:  # a training loop that checks the flag between steps
            steps += 1
            if steps == 3:
                send_sigint()
        assert stop.wait(1.0)
        assert steps == 3, "the loop saw the flag at the next check"
    assert recording_handler == [], "the previous handler does not see a SIGINT of the block"


def test_a_second_sigint_also_only_sets_the_flag(recording_handler):
    """The module documents one behaviour for every SIGINT in the block: the Event is set,
    nothing is raised (a second Ctrl-C does not force an exit)."""
    with stop_on_interrupt() as stop:
        send_sigint()
        assert stop.wait(1.0)
        send_sigint()
        send_sigint()
        assert stop.is_set()
    assert recording_handler == []


def test_the_previous_handler_is_restored_after_the_block(recording_handler):
    before = signal.getsignal(signal.SIGINT)
    with stop_on_interrupt() as stop:
        assert signal.getsignal(signal.SIGINT) is not before
    assert signal.getsignal(signal.SIGINT) is before
    send_sigint()
    assert recording_handler == [signal.SIGINT] and not stop.is_set()


def test_the_previous_handler_is_restored_when_the_block_raises(recording_handler):
    before = signal.getsignal(signal.SIGINT)
    with pytest.raises(RuntimeError):
        with stop_on_interrupt() as stop:
            send_sigint()
            raise RuntimeError("step failed")
    assert stop.is_set()
    assert signal.getsignal(signal.SIGINT) is before
    send_sigint()
    assert recording_handler == [signal.SIGINT]


def test_ctrl_c_raises_keyboard_interrupt_again_after_the_block():
    before = signal.signal(signal.SIGINT, signal.default_int_handler)  # Python's own, as a CLI run has it
    try:
        with stop_on_interrupt() as stop:
            send_sigint()
        assert stop.is_set()
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
        with pytest.raises(KeyboardInterrupt):
            send_sigint()
            time.sleep(1.0)  # not reached: the handler raises first
    finally:
        signal.signal(signal.SIGINT, before)


def test_nested_blocks_restore_each_others_handlers(recording_handler):
    with stop_on_interrupt() as outer:
        with stop_on_interrupt() as inner:
            send_sigint()
        assert inner.is_set() and not outer.is_set()
        send_sigint()
        assert outer.is_set()
    assert recording_handler == []


def test_outside_the_main_thread_the_flag_is_never_set_and_no_handler_changes(recording_handler):
    """Only the main thread may install a handler; a block in another thread must not try
    (signal.signal raises ValueError there) and leaves SIGINT to the main thread's handler."""
    before = signal.getsignal(signal.SIGINT)
    seen = {}
    entered, sent = threading.Event(), threading.Event()

    def worker():
        try:
            with stop_on_interrupt() as stop:
                seen["handler"] = signal.getsignal(signal.SIGINT)
                entered.set()
                sent.wait(5.0)
                seen["set"] = stop.is_set()
        except BaseException as err:  # noqa: BLE001 - reported below
            seen["error"] = err
            entered.set()

    thread = threading.Thread(target=worker)
    thread.start()
    assert entered.wait(5.0)
    send_sigint()
    sent.set()
    thread.join(5.0)
    assert "error" not in seen, seen.get("error")
    assert seen == {"handler": before, "set": False}
    assert recording_handler == [signal.SIGINT], "the main thread's handler got the SIGINT"
    assert signal.getsignal(signal.SIGINT) is before
