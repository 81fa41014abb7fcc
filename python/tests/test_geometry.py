"""Poses, point transforms and how points cross into the module (python/src/casters.h): numpy (n, 2) arrays in
and out, (x, y, theta) tuples, and the errors for arrays that are not point sets."""
import math

import numpy as np
import pytest

import partslam


def test_transform_known_answer():
    # Rotation by 90 degrees, then translation: (1, 0) -> (0, 1) -> (1, 3).
    out = partslam.transform((1.0, 2.0, math.pi / 2), np.array([[1.0, 0.0], [0.0, 0.0]]))
    assert out.dtype == np.float64 and out.shape == (2, 2)
    np.testing.assert_allclose(out, [[1.0, 3.0], [1.0, 2.0]], atol=1e-12)


def test_compose_and_inverse_agree_with_transform():
    rng = np.random.default_rng(4)
    points = rng.uniform(-5, 5, size=(20, 2))
    for _ in range(10):
        a = tuple(rng.uniform(-3, 3, 3))
        b = tuple(rng.uniform(-3, 3, 3))
        np.testing.assert_allclose(partslam.transform(partslam.compose(a, b), points),
                                   partslam.transform(a, partslam.transform(b, points)), atol=1e-12)
        identity = partslam.compose(a, partslam.inverse(a))
        np.testing.assert_allclose(identity, (0.0, 0.0, 0.0), atol=1e-12)


def test_wrap_centroid_and_bounding_box():
    assert partslam.wrap_angle(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
    assert partslam.wrap_angle(-math.pi) == pytest.approx(math.pi)
    points = np.array([[0.0, 1.0], [2.0, 3.0], [4.0, -1.0]])
    assert partslam.centroid(points) == pytest.approx((2.0, 1.0))
    assert partslam.bounding_box(points) == pytest.approx((0.0, 4.0, -1.0, 3.0))
    assert partslam.centroid(np.empty((0, 2))) == (0.0, 0.0)


def test_points_of_any_numeric_type_and_layout_are_taken():
    expected = np.array([[1.0, 2.0], [3.0, 4.0]])
    for points in ([[1, 2], [3, 4]], np.array([[1, 2], [3, 4]], dtype=np.int32),
                   np.array([[1, 2], [3, 4]], dtype=np.float32), np.asfortranarray(expected)):
        np.testing.assert_array_equal(partslam.transform((0.0, 0.0, 0.0), points), expected)
    empty = partslam.transform((1.0, 1.0, 0.0), np.empty((0, 2)))
    assert empty.shape == (0, 2)


def test_arrays_that_are_not_point_sets_raise_value_error_naming_the_problem():
    with pytest.raises(ValueError, match=r"shape \(n, 2\), got shape \(0,\)"):
        partslam.centroid(np.array([]))
    with pytest.raises(ValueError, match=r"got shape \(4, 3\)"):
        partslam.centroid(np.zeros((4, 3)))
    with pytest.raises(partslam.InputError, match=r"row 1 is not finite \(nan, 2.0\)"):
        partslam.centroid(np.array([[0.0, 0.0], [np.nan, 2.0]]))
    with pytest.raises(ValueError, match="row 0 is not finite"):
        partslam.centroid(np.array([[np.inf, 0.0]]))
    assert issubclass(partslam.InputError, ValueError)


def test_poses_are_three_numbers():
    with pytest.raises(TypeError):
        partslam.inverse((1.0, 2.0))
    assert partslam.inverse(np.array([0.0, 0.0, 0.5])) == pytest.approx((0.0, 0.0, -0.5))


@pytest.mark.parametrize("bad", [(math.nan, 0.0, 0.0), (0.0, math.inf, 0.0), (0.0, 0.0, -math.inf)])
def test_non_finite_poses_raise_naming_the_pose(bad):
    with pytest.raises(partslam.InputError, match=r"pose: \(x, y, theta\) must be finite"):
        partslam.compose(bad, (0.0, 0.0, 0.0))
    with pytest.raises(partslam.InputError, match="must be finite"):
        partslam.compose((0.0, 0.0, 0.0), bad)
    with pytest.raises(partslam.InputError, match="must be finite"):
        partslam.inverse(bad)
    with pytest.raises(partslam.InputError, match="must be finite"):
        partslam.transform(bad, np.zeros((1, 2)))
