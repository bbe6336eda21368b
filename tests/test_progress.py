"""Progress where stderr is not a terminal (nohup, CI, Slurm): plain lines, not a bar redrawn
with carriage returns, at the start, about every 30 s and at the end."""

import pytest

from objsearch.progress import progress_bar


def test_a_log_gets_plain_lines_with_done_total_rate_and_eta(capsys):
    bar = progress_bar(10, "random on gridworld", "ep", initial=4)
    bar.update(6)
    bar.close()
    err = capsys.readouterr().err
    assert "\r" not in err
    lines = err.splitlines()
    assert lines[0].startswith("random on gridworld: 4/10 ep, ") and "ETA" in lines[0]
    assert lines[-1].startswith("random on gridworld: 10/10 ep, ") and "ep/s" in lines[-1]


def test_lines_come_at_the_interval_not_at_every_update(capsys):
    bar = progress_bar(1000, "x", "ep")
    for _ in range(1000):
        bar.update()
    bar.close()
    assert len(capsys.readouterr().err.splitlines()) == 2, "the start and the end: 30 s did not pass"


@pytest.mark.parametrize("total", [0, 5])
def test_quiet_prints_nothing(capsys, total):
    bar = progress_bar(total, "x", "ep", enabled=False)
    bar.update(total)
    bar.close()
    assert capsys.readouterr().err == ""
