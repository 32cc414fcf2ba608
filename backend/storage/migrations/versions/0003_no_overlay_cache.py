"""Overlays are no longer kept: each is drawn for its request (a phone loads each answer's
overlay once; keeping them only wrote, then erased, megabytes per search).
"""

import sqlalchemy as sa
from alembic import op

revision, down_revision = "0003", "0002"


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
