"""Verify's work through the executor interface: local processes and a Dask cluster of two worker processes give the
same report, results in the tasks' order, a worker killed mid-run survived, the cluster extra asked for."""

from __future__ import annotations

import json
import os
import re
import signal
import sys
import threading
import time
from pathlib import Path

import pytest
from click.testing import CliRunner
from executor_tasks import echo_after, logged

from codegen.cli import main
from codegen.dialects.core.values import RunError
from codegen.model.cell import EXAMPLES_DIR, load_cell
from codegen.plant.executors import DaskExecutor, LocalExecutor
from codegen.verify.engine import CellRun, Options, verify_cell, verify_cells
from codegen.verify.runner import run_chunk

CELL = EXAMPLES_DIR / "thermometer_bench.toml"  # the quickest example to verify on one target
TARGET = "dtrans"
TIMING = ("seconds", "cases_per_second", "wall_seconds")  # how long it took: the only figures a run may change


def _untimed(data):
    """One cell's report without its times."""
    if isinstance(data, dict):
        return {k: _untimed(v) for k, v in data.items() if k not in TIMING}
    if isinstance(data, list):
        return [_untimed(v) for v in data]
    return data


def _text_untimed(lines: list[str]) -> list[str]:
    """The text report without its times: the cases/s column and the wall seconds."""
    out = []
    for line in lines:
        line = re.sub(r" in \d+\.\d s wall,", " in - s wall,", line)
        out.append(re.sub(r"(\d\.\d\de[-+]\d\d)\s+\d+$", r"\1 -", line))
    return out


def test_local_results_come_in_the_tasks_order():
    tasks = [(i, 0.3 - 0.1 * i) for i in range(3)]
    for groups in (None, [0, 1, 0]):
        results = list(LocalExecutor(jobs=2).map(echo_after, tasks, groups))
        assert [value for value, _pid in results] == [0, 1, 2]
        assert len({pid for _value, pid in results}) == 2  # in two processes, not one after the other
    assert [v for v, _ in LocalExecutor(jobs=1).map(echo_after, tasks)] == [0, 1, 2]


def test_verify_cells_reports_each_cell_and_a_bad_cell_alone(tmp_path):
    """Two cells in one run: the good one's report is verify_cell's; the other's files are not its programs, its
    error comes in its place."""
    cell = load_cell(CELL)
    stray = tmp_path / "stray.prg"
    stray.write_text("no program of this cell\n")
    options = Options(cases=1, seed=4, jobs=1, sweeps=False)
    good, bad = verify_cells([CellRun(cell, (), (TARGET,)), CellRun(cell, (str(stray),), (TARGET,))], options)
    alone = verify_cell(cell, targets=(TARGET,), options=options)
    assert _untimed(good.as_json()) == _untimed(alone.as_json())
    assert good.ok and sum(r.cases for r in good.rows) > 100
    assert isinstance(bad, RunError) and f"{stray}:1:" in str(bad)


def test_scheduler_without_distributed_says_which_extra(monkeypatch):
    """--scheduler (or the scheduler's environment variable) without the distributed package: exit 2, the extra."""
    monkeypatch.setitem(sys.modules, "distributed", None)  # its import fails as where it is not installed
    runner = CliRunner()
    for args, env in (
        (["--scheduler", "tcp://127.0.0.1:1"], {}),
        ([], {"DASK_SCHEDULER_ADDRESS": "tcp://127.0.0.1:1"}),
    ):
        result = runner.invoke(main, ["verify", str(CELL), "--target", TARGET, "--cases", "1", *args], env=env)
        assert result.exit_code == 2, result.output
        assert "pip install 'codegen[cluster]'" in result.output and "Traceback" not in result.output


@pytest.fixture(scope="module")
def cluster():
    """A local Dask cluster of two worker processes, one thread each (distributed: the test extra)."""
    distributed = pytest.importorskip("distributed", reason="distributed is not installed (codegen[cluster])")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=50
    ) as local:
        yield local


@pytest.fixture
def client(cluster):
    from distributed import Client

    with Client(cluster, set_as_default=False) as made:
        made.wait_for_workers(2)
        yield made


def test_cluster_results_come_in_the_tasks_order(client):
    tasks = [(i, 0.4 - 0.1 * i) for i in range(4)]
    with DaskExecutor(client) as executor:
        assert executor.workers == 2
        for groups in (None, [0, 1, 0, 1]):
            results = list(executor.map(echo_after, tasks, groups))
            assert [value for value, _pid in results] == [0, 1, 2, 3]
            assert len({pid for _value, pid in results}) == 2


def test_a_cluster_run_gives_the_local_report(client):
    """The same cell, seed and cases on the cluster and in local processes: the same report but for its times."""
    cell = load_cell(CELL)
    local = verify_cell(cell, targets=(TARGET,), options=Options(cases=1, seed=7, jobs=2, sweeps=False))
    with DaskExecutor(client) as executor:
        spread = verify_cell(cell, targets=(TARGET,), options=Options(cases=1, seed=7, sweeps=False, executor=executor))
    assert local.ok and sum(r.cases for r in local.rows) > 100
    assert json.dumps(_untimed(spread.as_json())) == json.dumps(_untimed(local.as_json()))
    assert _text_untimed(spread.lines()) == _text_untimed(local.lines())


class _Logging:
    """An executor whose tasks log their starts."""

    def __init__(self, executor, log: Path) -> None:
        self.executor, self.log = executor, log
        self.workers = executor.workers

    def map(self, fn, tasks, groups=None):
        return self.executor.map(logged, [(str(self.log), i, fn, t) for i, t in enumerate(tasks)], groups)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return None


def _kill_first_case_batch(log: Path, killed: list) -> None:
    """Kills the worker process of the first case batch as soon as it starts."""
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline:
        lines = log.read_text().splitlines() if log.exists() else []
        started = [line.split() for line in lines if line.startswith(run_chunk.__name__)]
        if started:
            _name, index, pid = started[0]
            os.kill(int(pid), signal.SIGKILL)
            killed.append((index, pid))
            return
        time.sleep(0.01)


@pytest.mark.slow  # a worker restarts and the batches run again: many seconds on two cores
def test_a_worker_killed_mid_run_is_survived(client, tmp_path):
    """A worker process killed while it runs a case batch: the batch runs again on a worker, and the report is the
    local one: no case lost, none counted twice."""
    cell = load_cell(CELL)
    options = Options(cases=3, seed=11, jobs=2, sweeps=False)
    local = verify_cell(cell, targets=(TARGET,), options=options)
    log, killed = tmp_path / "starts.log", []
    killer = threading.Thread(target=_kill_first_case_batch, args=(log, killed))
    killer.start()
    with DaskExecutor(client) as executor:
        spread = verify_cell(
            cell, targets=(TARGET,), options=Options(3, 11, sweeps=False, executor=_Logging(executor, log))
        )
    killer.join()
    assert killed, "no case batch started"
    index, pid = killed[0]
    runs = [line.split() for line in log.read_text().splitlines() if line.startswith(run_chunk.__name__)]
    again = [other for name, i, other in runs if i == index]
    assert len(again) >= 2 and again[0] == pid and pid not in again[1:]  # run again, in another process
    assert _untimed(spread.as_json()) == _untimed(local.as_json())
    assert sum(r.cases for r in spread.rows) == sum(r.cases for r in local.rows)


@pytest.mark.slow  # two whole verify runs from the command line
def test_verify_scheduler_prints_the_local_report(cluster):
    """`codegen verify --scheduler ADDRESS` and `--jobs 2`: the same text and JSON but for their times."""
    base = ["verify", str(CELL), "--target", TARGET, "--cases", "1", "--seed", "5"]
    runner = CliRunner()
    outputs = []
    for where in (["--jobs", "2"], ["--scheduler", cluster.scheduler_address]):
        text = runner.invoke(main, [*base, *where])
        data = runner.invoke(main, [*base, *where, "--json"])
        assert text.exit_code == 0 and data.exit_code == 0, text.output + data.output
        outputs.append((_text_untimed(text.output.splitlines()), _untimed(json.loads(data.output))))
    assert outputs[0] == outputs[1]
    assert "2 worker(s)" in outputs[1][0][-2]


def _small_plant(tmp_path: Path, names=("pallets/tray_dtrans.toml", "stations/warehouse_dtrans.toml")) -> Path:
    """A plant of copies of the example plant's cells."""
    from codegen.model.cell import EXAMPLE_PLANT

    plant = tmp_path / "plant"
    plant.mkdir()
    for name in names:
        (plant / Path(name).name).write_bytes((EXAMPLE_PLANT / name).read_bytes())
    return plant


def test_a_plants_report_is_the_same_bytes_on_one_worker_or_two_at_any_speed(tmp_path, monkeypatch):
    """`codegen verify PLANT --json`: in this process with a clock running seven times as fast, and on two worker
    processes with the real one: the same bytes (the times are in --timings' file alone)."""
    plant = _small_plant(tmp_path, ("pallets/tray_dtrans.toml",))  # the pallet: its rows have a time of their own
    common = ["verify", str(plant), "--cases", "1", "--seed", "2", "--no-cache", "--json"]
    runner = CliRunner()
    spread = runner.invoke(main, [*common, "--jobs", "2", "--timings", str(tmp_path / "two.json")])
    real = time.perf_counter
    monkeypatch.setattr(time, "perf_counter", lambda: 7 * real())
    alone = runner.invoke(main, [*common, "--jobs", "1", "--timings", str(tmp_path / "one.json")])
    assert spread.exit_code == 0 and alone.exit_code == 0, spread.output + alone.output
    assert alone.output == spread.output
    times = [json.loads((tmp_path / f"{n}.json").read_text())["cells"][0]["data"] for n in ("one", "two")]
    assert [t["workers"] for t in times] == [1, 2]  # how it ran: in the times, not the report


@pytest.mark.slow
def test_a_plant_verified_on_the_cluster_gives_the_local_report(cluster, tmp_path):
    """`codegen verify PLANT --scheduler ADDRESS`: two cells of the example plant on the two-worker cluster and in
    local processes, with no stored results: the same report, byte for byte."""
    plant = _small_plant(tmp_path)
    common = ["verify", str(plant), "--cases", "1", "--seed", "3", "--no-cache", "--json"]
    runner = CliRunner()
    local = runner.invoke(main, [*common, "--jobs", "2"])
    spread = runner.invoke(main, [*common, "--scheduler", cluster.scheduler_address])
    assert local.exit_code == 0, local.output
    assert spread.exit_code == 0, spread.output
    assert [row["result"] for row in json.loads(local.output)["rows"]] == ["ok", "ok"]
    assert spread.output == local.output
