"""The rendered halls are what they claim: stored-size photos, true geometry, landmarks that
both photos show where the cameras put them, the same photos for the same seed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from testbed.render import Surface, render
from testbed.scenes import Camera, look_at
from testbed.textures import Texture
from testbed.venue import STORED_SIDE, RenderedPair, rendered_pair


@pytest.fixture(scope="module")
def pair() -> RenderedPair:
    return rendered_pair(7)


def test_photos_are_stored_size_and_the_geometry_holds(pair: RenderedPair) -> None:
    scene = pair.scene
    for photo, size in ((pair.photo1, scene.image_size1), (pair.photo2, scene.image_size2)):
        assert photo.dtype == np.uint8
        assert photo.shape == (size[1], size[0], 3)
        assert max(size) == STORED_SIDE
    assert len(scene.points) >= 10
    assert len(pair.kinds) == len(pair.normals) == len(scene.points)
    # Every landmark is on the epipolar line of its partner, and in front of both cameras.
    p = np.column_stack([scene.landmarks1, np.ones(len(scene.points))])
    q = np.column_stack([scene.landmarks2, np.ones(len(scene.points))])
    residual = np.abs(np.einsum("ni,ij,nj->n", q, scene.fundamental, p))
    assert residual.max() < 1e-9 * np.abs(scene.fundamental).max() * STORED_SIDE**2
    assert (scene.camera1.depth(scene.points) > 0).all()
    assert (scene.camera2.depth(scene.points) > 0).all()
    # Each friend is in the other's photo.
    for point, size in ((scene.epipole1, scene.image_size1), (scene.epipole2, scene.image_size2)):
        assert 0 <= point[0] <= size[0]
        assert 0 <= point[1] <= size[1]


def test_spots_one_photo_shows_are_hidden_from_the_other(pair: RenderedPair) -> None:
    scene = pair.scene
    assert len(pair.only1) > 0
    assert len(pair.only2) > 0
    # Shared landmarks and spots of one photo only are different places.
    for only in (pair.only1, pair.only2):
        gaps = np.linalg.norm(only[:, None, :] - scene.points[None, :, :], axis=2)
        assert gaps.min() > 0


def test_the_same_seed_renders_the_same_photos(pair: RenderedPair) -> None:
    again = rendered_pair(7)
    assert np.array_equal(pair.photo1, again.photo1)
    assert np.array_equal(pair.photo2, again.photo2)
    assert np.array_equal(pair.scene.points, again.scene.points)
    assert not np.array_equal(pair.photo1, rendered_pair(12, max_landmarks=5).photo1)


def test_a_plane_renders_where_its_homography_puts_it_and_occludes_what_is_behind() -> None:
    """A chequered square 10 m ahead, and a red one in front of half of it."""
    chequer = np.zeros((200, 200, 3), np.uint8)
    chequer[:100, :100] = chequer[100:, 100:] = 255
    red = np.zeros((50, 50, 3), np.uint8)
    red[:] = (0, 0, 255)
    far = Surface(
        np.array([-2.0, -2.0, 10.0]),
        np.array([4.0, 0.0, 0.0]),
        np.array([0.0, 4.0, 0.0]),
        Texture(chequer, np.zeros((0, 2))),
    )
    near = Surface(
        np.array([-0.5, -0.5, 5.0]),
        np.array([0.5, 0.0, 0.0]),
        np.array([0.0, 1.0, 0.0]),
        Texture(red, np.zeros((0, 2))),
    )
    rotation, translation = look_at(np.zeros(3), np.array([0.0, 0.0, 1.0]))
    camera = Camera(np.array([[500.0, 0, 320], [0, 500.0, 240], [0, 0, 1]]), rotation, translation)
    image, inverse_depth = render([far, near], camera, (640, 480))
    # The far square spans +-2 m at 10 m: +-100 px around the centre (its top-left corner at
    # (220, 140)); the texture's top-left quarter, which is white, is the photo's.
    corner = camera.project(np.array([[-2.0, -2.0, 10.0]]))[0]
    np.testing.assert_allclose(corner, [220.0, 140.0], atol=1e-9)
    assert image[170, 250].mean() > 200
    assert image[170, 350].mean() < 50
    # The red square (5 m away) hides the chequer: red, at twice the chequer's inverse depth.
    centre = np.round(camera.project(np.array([[-0.25, 0.0, 5.0]]))[0]).astype(int)
    assert image[centre[1], centre[0], 2] > 200
    assert image[centre[1], centre[0], 0] < 50
    assert math.isclose(inverse_depth[centre[1], centre[0]], 1 / 5, rel_tol=1e-6)
    assert math.isclose(inverse_depth[240, 400], 1 / 10, rel_tol=1e-6)
    # Nothing behind the camera or beyond the planes is drawn.
    assert inverse_depth[5, 5] == 0
