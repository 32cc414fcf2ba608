"""A photo keeps which way the lens looked at the shutter, when the phone's compass read it
(the app's own camera): ``photos.heading``, degrees clockwise from north in [0, 360), and
``photos.heading_sigma_deg``. Photos stored before have none."""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision, down_revision = "0012", "0011"


def upgrade() -> None:
    op.add_column("photos", sa.Column("heading", sa.Float(), nullable=True))
    op.add_column("photos", sa.Column("heading_sigma_deg", sa.Float(), nullable=True))


def downgrade() -> None:
    # DROP COLUMN, which SQLite runs in place from 3.35 (Debian 12 has 3.40).
    op.drop_column("photos", "heading_sigma_deg")
    op.drop_column("photos", "heading")
