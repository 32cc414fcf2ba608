"""Overlays are no longer kept: each is drawn for its request (a phone loads each answer's
overlay once; keeping them only wrote, then erased, megabytes per search).

Revision ID: 0003
Revises: 0002
Create Date: 2026-11-21
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0003"
down_revision = "0002"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.drop_table("overlays")


def downgrade() -> None:
    op.create_table(
        "overlays",
        sa.Column(
            "session_id",
            sa.String(32),
            sa.ForeignKey("sessions.id", ondelete="CASCADE"),
            nullable=False,
            primary_key=True,
        ),
        sa.Column("role", sa.String(6), primary_key=True),
        sa.Column("format", sa.String(4), primary_key=True),
        sa.Column("version", sa.Integer(), nullable=False),
        sa.Column("data", sa.LargeBinary(), nullable=False),
    )
