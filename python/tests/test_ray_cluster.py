"""`dbot.vector_pool.RolloutPool` on a two-node Ray cluster started on this machine
(`ray.cluster_utils.Cluster`: a head and one worker node, one CPU each, on loopback): one actor
per node holds a `VectorEnv`, rollouts go to it in chunks, every rollout runs (rows from both
node ids), and the rows equal those of one process (the robots are deterministic). One cluster
for the module: Ray's start and stop cost seconds.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from conftest import need_module
from dbot.env import VectorEnv
from dbot.vector_pool import RolloutPool, _chunks, residual_walks

STEPS = 40
MAKE_ENV = functools.partial(VectorEnv, 1, threads=0, max_episode_steps=STEPS, torques=True)
WALK = functools.partial(residual_walks, steps=STEPS)


@pytest.fixture(scope="module")
def cluster():
    need_module("ray")
    import ray
    from ray.cluster_utils import Cluster

    c = Cluster(initialize_head=True, head_node_args={"num_cpus": 1})
    c.add_node(num_cpus=1)
    c.wait_for_nodes()
    ray.init(address=c.address, include_dashboard=False, log_to_driver=False)
    yield c
    ray.shutdown()
    c.shutdown()


def test_chunks_are_contiguous_and_cover_every_item() -> None:
    assert _chunks(list(range(5)), 2) == [[0, 1, 2], [3, 4]]
    assert _chunks([1], 4) == [[1]]


def test_every_rollout_runs_on_both_nodes_with_the_rows_of_one_process(cluster) -> None:
    rng = np.random.default_rng(5)
    thetas = [rng.normal(0.0, 0.5, 66) for _ in range(4)]
    with RolloutPool(MAKE_ENV, backend="serial") as one:
        expected = one.map(WALK, thetas)
    with RolloutPool(MAKE_ENV, backend="ray", workers=2) as pool:
        rows = pool.map(WALK, thetas)
        nodes = pool.nodes
    assert rows == expected
    assert nodes is not None and len(nodes) == len(thetas)
    assert len(set(nodes)) == 2
    assert {n["NodeID"] for n in __import__("ray").nodes() if n["Alive"]} == set(nodes)
