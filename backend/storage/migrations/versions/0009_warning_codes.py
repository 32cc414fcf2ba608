"""An answer's warnings are codes with parameters and a sentence, no longer bare sentences:
stored answers, whose shape changed, are cleared, and the next read of the state answers
again (``TapService.due``), as migration 0006 did.

Revision ID: 0009
Revises: 0008
Create Date: 2026-11-26
"""

from __future__ import annotations

from alembic import op

revision = "0009"
down_revision = "0008"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.execute("UPDATE sessions SET answer = NULL, answer_version = NULL")


def downgrade() -> None:
    # The warnings' old shape cannot be made from the new one without the sentences' routing
    # it replaced: clear them the same way.
    op.execute("UPDATE sessions SET answer = NULL, answer_version = NULL")
