"""The old name of :mod:`.pictures`, kept only for ``backend/taps/service.py``.

Issue 22 split this module into :mod:`.intake`, :mod:`.exif` and :mod:`.pictures`; the taps
domain was being changed by others at the time, so its one import line moves when that
work merges: ``from backend.photos.pictures import decode_photo, encode_image,
encode_layer``. Then this file goes. Nothing else may import it (tests/backend/
test_photo_modules.py checks).
"""

from __future__ import annotations

from .pictures import decode_photo, encode_image, encode_layer

__all__ = ["decode_photo", "encode_image", "encode_layer"]
