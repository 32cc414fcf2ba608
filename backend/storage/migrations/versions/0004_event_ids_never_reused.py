"""Event ids are never reused on SQLite either (AUTOINCREMENT). Without it SQLite gives a
new row the id after the largest left, so deleting the newest session's events let new
events take ids that other processes' watchers had already looked past. PostgreSQL's
sequences never reuse ids: nothing changes there.

Revision ID: 0004
Revises: 0003
Create Date: 2026-11-21
"""

from __future__ import annotations

from alembic import op

revision = "0004"
down_revision = "0003"
branch_labels = None
depends_on = None


def upgrade() -> None:
    _rebuild_events(autoincrement=True)


def downgrade() -> None:
    _rebuild_events(autoincrement=False)


def _rebuild_events(*, autoincrement: bool) -> None:
    if op.get_bind().dialect.name != "sqlite":
        return
    with op.batch_alter_table(
        "events", recreate="always", table_kwargs={"sqlite_autoincrement": autoincrement}
    ):
        pass
