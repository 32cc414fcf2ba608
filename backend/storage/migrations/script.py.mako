"""${message}"""

import sqlalchemy as sa
from alembic import op
${imports if imports else ""}
# Alembic reads these two names (branch_labels and depends_on default to none); the
# revision's date is in git.
revision, down_revision = ${repr(up_revision)}, ${repr(down_revision)}


def upgrade() -> None:
    ${upgrades if upgrades else "pass"}


def downgrade() -> None:
    ${downgrades if downgrades else "pass"}
