"""Each photo records the session's version that stored it: with the session and the role,
that names its bytes, so a replica can keep the photos it read lately (the crops of the
landmarks being found) without asking the database whether they changed. Photos stored
before have none, and are read each time.
"""

import sqlalchemy as sa
from alembic import op

revision, down_revision = "0008", "0007"


def upgrade() -> None:
    op.add_column("photos", sa.Column("version", sa.Integer(), nullable=True))


def downgrade() -> None:
    if op.get_bind().dialect.name == "sqlite":  # SQLite drops a column in place
        op.execute("ALTER TABLE photos DROP COLUMN version")
    else:
        op.drop_column("photos", "version")
