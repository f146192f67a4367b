"""10 000 calls of emrm.simulate, each reading its fields and arrays, leave the memory where it
was after the first thousand: nothing of a result outlives it."""

import gc
import os

import emrm


def resident_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def simulate_and_read():
    result = emrm.simulate(speed_kph=50, ttc_s=1.2)  # bench_simulate's BM_CellGreen
    outcome = result.strategies["emergency_stop"]
    trajectory = outcome.trajectory
    assert result.region == "G" and outcome.avoided
    return trajectory.x.sum() + trajectory.v[-1] + outcome.truck_trajectory.y[0] + len(result.unmitigated)


def test_ten_thousand_simulations_keep_memory_flat():
    for _ in range(1000):  # warm-up: the allocator's pools, NumPy's caches
        simulate_and_read()
    gc.collect()
    before = resident_bytes()
    for _ in range(10_000):
        simulate_and_read()
    gc.collect()
    growth = resident_bytes() - before
    print(f"resident memory grew by {growth / 1024:.0f} KiB over 10 000 simulations")
    assert growth < 4 * 1024 * 1024
