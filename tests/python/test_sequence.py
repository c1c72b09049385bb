"""skelseg.sequence_consensus: the choice of `skelseg sequence` on label arrays."""
import itertools

import numpy as np
import pytest

import skelseg


def test_the_most_typical_frame_of_the_modal_part_count_is_chosen():
    # Frames 0 and 2 have 3 parts, frame 1 has 2 and is the nearest to all,
    # but the count most frames have is 3: frame 2, the nearer of those two.
    frames = [np.array([0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2]),
              np.array([5, 5, 5, 5, 7, 7, 7, 7, 7, 7, 7, 7]),
              np.array([1, 3, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4])]
    c = skelseg.sequence_consensus(frames)
    assert isinstance(c, skelseg.SequenceConsensus)
    assert c.parts == (3, 2, 3)
    assert c.modal_parts == 3
    assert c.reference == 2
    assert c.mean_error_to_others[1] < c.mean_error_to_others[2] < c.mean_error_to_others[0]


def test_pair_errors_are_the_rand_index_errors_of_score():
    rng = np.random.default_rng(7)
    frames = [rng.integers(0, k, size=200) for k in (2, 3, 3, 4)]
    c = skelseg.sequence_consensus(frames)
    assert c.pair_errors.shape == (4, 4)
    for a, b in itertools.product(range(4), repeat=2):
        expected = 0.0 if a == b else skelseg.score(frames[a], frames[b]).rand_index_error
        assert c.pair_errors[a, b] == pytest.approx(expected, abs=1e-12)
    pairs = [c.pair_errors[a, b] for a, b in itertools.combinations(range(4), 2)]
    assert c.mean_pair_error == pytest.approx(np.mean(pairs), abs=1e-12)
    assert c.mean_error_to_others[0] == pytest.approx(np.mean(c.pair_errors[0, 1:]), abs=1e-12)


def test_lists_of_ints_are_accepted_and_a_tie_goes_to_the_earlier_frame():
    c = skelseg.sequence_consensus([[0, 0, 1, 1], [0, 1, 1, 2]])
    assert c.reference == 0


@pytest.mark.parametrize("frames", [[], [np.array([0, 1])], [np.array([0, 1]), np.array([0, 1, 2])],
                                    [np.array([], dtype=np.int64)] * 2])
def test_bad_sequences_raise_value_error(frames):
    with pytest.raises(ValueError):
        skelseg.sequence_consensus(frames)


@pytest.mark.parametrize("scalar", [3, 2.5, np.int64(3), np.array(3), np.array([[0, 1]])[0, 0]])
def test_a_scalar_instead_of_frames_is_a_value_error(scalar):
    with pytest.raises(ValueError, match=r"^frame_labels must be a sequence of per-frame label "
                                         r"arrays, not the scalar "):
        skelseg.sequence_consensus(scalar)


def test_integer_valued_float_frames_are_type_errors_not_cast():
    with pytest.raises(TypeError, match=r"^frame_labels must be integers, not float64 "):
        skelseg.sequence_consensus([np.array([0.0, 0.0, 1.0, 1.0]), np.array([0, 1, 1, 2])])


def test_frames_not_trusted_neither_vote_nor_are_chosen():
    # Frames 0 and 1 have 3 parts but are not trusted; frame 2 is the only
    # trusted frame: its 2 parts are the vote and it is the reference.
    frames = [np.array([0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2]),
              np.array([0, 0, 0, 1, 1, 1, 1, 1, 2, 2, 2, 2]),
              np.array([5, 5, 5, 5, 5, 5, 5, 5, 7, 7, 7, 7])]
    every = skelseg.sequence_consensus(frames)
    assert (every.reference, every.modal_parts) == (1, 3)
    assert every.voted == (True, True, True)
    c = skelseg.sequence_consensus(frames, trusted=[False, False, True])
    assert (c.reference, c.modal_parts) == (2, 2)
    assert c.voted == (False, False, True)
    np.testing.assert_array_equal(c.pair_errors, every.pair_errors)
    assert skelseg.sequence_consensus(frames, trusted=[False] * 3).reference == every.reference
    with pytest.raises(ValueError, match="trust is given for 2 frames, the sequence has 3"):
        skelseg.sequence_consensus(frames, trusted=[True, False])


def test_numbers_or_a_dict_as_frames_are_refused():
    # A number became a frame of one face: [0, 1] was two one-face frames,
    # and a dict gave its keys.
    with pytest.raises(ValueError, match=r"^frame_labels must be 1-D arrays of labels"):
        skelseg.sequence_consensus([0, 1])
    with pytest.raises(TypeError, match=r"not a dict"):
        skelseg.sequence_consensus({0: np.array([0, 1]), 1: np.array([1, 0])})
    with pytest.raises(ValueError, match=r"^labels must be 1-D arrays of labels"):
        skelseg.score(3, [3])
    with pytest.raises(ValueError, match=r"^human_labels must be 1-D arrays of labels"):
        skelseg.score(np.array([0, 1]), [np.array([[0, 1]])])
