"""skelseg.segment mapped over generated shapes on a Dask cluster of two
worker processes: the results equal direct calls."""
import os

import numpy as np
import pytest

import skelseg

distributed = pytest.importorskip("distributed")

SHAPES = [("figure", 96, 0), ("figure", 96, 1), ("figure", 96, 2), ("y-arms", 48, 0),
          ("y-arms", 64, 0), ("box-tubes", 48, 0)]


# Debian's tornado and distributed 2022.12 disagree on event loop set-up; harmless.
@pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")
def test_client_map_over_six_shapes_on_a_local_cluster_equals_direct_calls(shapes):
    masks = [skelseg.read_volume(shapes.nrrd(*shape)) for shape in SHAPES]
    expected = [skelseg.segment(mask) for mask in masks]
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        futures = client.map(skelseg.segment, masks, tau="3%", pure=False)
        results = client.gather(futures)
        worker_pids = set(client.run(os.getpid).values())
    assert len(worker_pids) == 2 and os.getpid() not in worker_pids  # two worker processes
    for result, direct in zip(results, expected):
        assert isinstance(result, skelseg.SegmentationResult)
        np.testing.assert_array_equal(result.labels, direct.labels)
        np.testing.assert_array_equal(result.skeleton.points, direct.skeleton.points)
        assert result.n_segments == direct.n_segments >= 2
        assert len(result.cuts) == len(direct.cuts)
