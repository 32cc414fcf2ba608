"""Maximum a posteriori two-view geometry of two pinhole cameras (square pixels, centred).

The model: camera 1 (friend 1's) sees friend 2 in the direction ``b1`` (unit, frame 1);
frame 2 is ``X2 = R X1 + t`` with ``t`` along ``-R b1``; each camera has its own focal
length ``f_k`` (px) and its principal point at the photo's centre ``c_k``. Then

    F = K2^-T R [b1]x K1^-1,   e1 ~ K1 b1,   e2 ~ -K2 R b1   (oriented: w > 0 in front),

and a landmark with rays ``p^ = K1^-1 p``, ``q^ = K2^-1 q`` fits when ``q^ . R (b1 x p^) = 0``
(Hartley & Zisserman 9.6). Seven parameters: the rotation (3), friend 2's direction (2)
and the two log focal lengths (2), the last with the cameras' priors (:mod:`..camera`).

By job, each importing only those before it:

- :mod:`.pose`: the parameter space, K poses at once, and tangent steps in it;
- :mod:`.predictions`: where a pose puts each friend, and its F, with derivatives;
- :mod:`.model`: every tap's whitened residual against those predictions;
- :mod:`.propagation`: first-order covariances of the predictions;
- :mod:`.fit`: the fit (Levenberg-Marquardt) and what it gives;
- :mod:`.starts`: where the fit starts, every pose the exact solvers allow, ranked;
- :mod:`.mistaps`: the mis-tapped landmarks, found by consensus over sets of three.
"""
