"""Failed joins by client address: what the join-code guessing limits count."""

import sqlalchemy as sa
from alembic import op

revision, down_revision = "0002", "0001"


def upgrade() -> None:
    op.create_table(
        "join_failures",
        sa.Column("id", sa.Integer(), primary_key=True, autoincrement=True),
        sa.Column("client", sa.String(64), nullable=False),
        sa.Column("failed_at", sa.DateTime(), nullable=False),
    )
    # One client's failures in the window; everyone's in the window (and the pruning).
    op.create_index("ix_join_failures_client_failed_at", "join_failures", ["client", "failed_at"])
    op.create_index("ix_join_failures_failed_at", "join_failures", ["failed_at"])


def downgrade() -> None:
    op.drop_table("join_failures")
