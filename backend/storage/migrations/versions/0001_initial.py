"""The initial schema: sessions, with their participants, photos, overlays and events.

Exactly what ``Base.metadata.create_all`` made before there were migrations, so such a
database is stamped as this revision (``migrate``) rather than created again.
"""

import sqlalchemy as sa
from alembic import op

revision, down_revision = "0001", None


def _session_id(*, primary_key: bool = False, index: bool = False) -> sa.Column[str]:
    """A row's session: everything of a session goes with it (ON DELETE CASCADE)."""
    return sa.Column(
        "session_id",
        sa.String(32),
        sa.ForeignKey("sessions.id", ondelete="CASCADE"),
        nullable=False,
        primary_key=primary_key,
        index=index,
    )


def upgrade() -> None:
    op.create_table(
        "sessions",
        sa.Column("id", sa.String(32), primary_key=True),
        sa.Column("created_at", sa.DateTime(), nullable=False),
        sa.Column("expires_at", sa.DateTime(), nullable=False, index=True),
        sa.Column("join_code", sa.String(6), unique=True),
        sa.Column("join_code_expires_at", sa.DateTime()),
        sa.Column("version", sa.Integer(), nullable=False),
        sa.Column("result", sa.Text()),
        sa.Column("result_version", sa.Integer()),
    )
    op.create_table(
        "participants",
        sa.Column("id", sa.Integer(), primary_key=True, autoincrement=True),
        _session_id(index=True),
        sa.Column("role", sa.String(6), nullable=False),
        sa.Column("token_hash", sa.String(64), nullable=False, unique=True),
        sa.Column("joined_at", sa.DateTime(), nullable=False),
        sa.Column("last_seen_at", sa.DateTime()),
        sa.Column("taps", sa.Text()),
        sa.UniqueConstraint("session_id", "role"),
    )
    op.create_table(
        "photos",
        _session_id(primary_key=True),
        sa.Column("role", sa.String(6), primary_key=True),
        sa.Column("data", sa.LargeBinary(), nullable=False),  # bytea on PostgreSQL
        sa.Column("width", sa.Integer(), nullable=False),
        sa.Column("height", sa.Integer(), nullable=False),
        sa.Column("scale", sa.Float(), nullable=False),
        sa.Column("uploaded_at", sa.DateTime(), nullable=False),
    )
    op.create_table(
        "overlays",
        _session_id(primary_key=True),
        sa.Column("role", sa.String(6), primary_key=True),
        sa.Column("format", sa.String(4), primary_key=True),
        sa.Column("version", sa.Integer(), nullable=False),
        sa.Column("data", sa.LargeBinary(), nullable=False),
    )
    op.create_table(
        "events",
        sa.Column("id", sa.Integer(), primary_key=True, autoincrement=True),
        _session_id(index=True),
        sa.Column("type", sa.String(16), nullable=False),
        sa.Column("data", sa.Text(), nullable=False),
        sa.Column("created_at", sa.DateTime(), nullable=False),
    )


def downgrade() -> None:
    for table in ("events", "overlays", "photos", "participants", "sessions"):
        op.drop_table(table)
