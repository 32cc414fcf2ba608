"""Event ids are never reused on SQLite either (AUTOINCREMENT). Without it SQLite gives a
new row the id after the largest left, so deleting the newest session's events let new
events take ids that other processes' watchers had already looked past. PostgreSQL's
sequences never reuse ids: nothing changes there.
"""

from alembic import op

revision, down_revision = "0004", "0003"


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
