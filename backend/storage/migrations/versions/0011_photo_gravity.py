"""A photo keeps which way was down at the shutter, when the phone read it (the app's own
camera): ``photos.gravity``, JSON ``[x, y, z, sigma_deg]``. Photos stored before have none."""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision, down_revision = "0011", "0010"


def upgrade() -> None:
    op.add_column("photos", sa.Column("gravity", sa.Text(), nullable=True))


def downgrade() -> None:
    # DROP COLUMN, which SQLite runs in place from 3.35 (Debian 12 has 3.40).
    op.drop_column("photos", "gravity")
