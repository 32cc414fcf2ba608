"""Join codes of eight digits (a search number, then a secret), with the wrong codes that
named a search counted on its row, and how many times its code was renewed.

SQLite keeps the column's type as it is: it does not enforce a VARCHAR's length, and
changing a type there means copying the table, whose drop would delete every session's rows
through the foreign keys.

Six-digit codes still live at the upgrade no longer match what the API accepts: they are
cleared, so those seekers' phones show that the code ran out (a new search gets a new one).
"""

import sqlalchemy as sa
from alembic import op

revision, down_revision = "0005", "0004"


COUNTS = ("join_code_failures", "join_code_renewals")


def upgrade() -> None:
    op.execute("UPDATE sessions SET join_code = NULL, join_code_expires_at = NULL")
    for name in COUNTS:
        op.add_column("sessions", sa.Column(name, sa.Integer(), nullable=False, server_default="0"))
    _code_length(8)


def downgrade() -> None:
    op.execute("UPDATE sessions SET join_code = NULL, join_code_expires_at = NULL")
    _code_length(6)
    if op.get_bind().dialect.name == "sqlite":
        for name in COUNTS:  # SQLite drops a column in place (3.35 and later)
            op.execute(f"ALTER TABLE sessions DROP COLUMN {name}")
        return
    for name in COUNTS:
        op.drop_column("sessions", name)


def _code_length(digits: int) -> None:
    if op.get_bind().dialect.name == "sqlite":
        return
    op.alter_column(
        "sessions",
        "join_code",
        type_=sa.String(digits),
        existing_type=sa.String(14 - digits),
        existing_nullable=True,
    )
