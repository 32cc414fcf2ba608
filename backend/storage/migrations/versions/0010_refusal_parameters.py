"""An answer's refusal is its code, reason and parameters and a sentence, no longer a code
and a sentence naming photo 1 and photo 2 (which each phone was told by rewriting it): a
stored refusal of the old shape has nothing to word it from for each phone, so stored
answers are cleared, and the next read of the state answers again (``TapService.due``), as
migration 0009 did.

Revision ID: 0010
Revises: 0009
Create Date: 2026-11-26
"""

from __future__ import annotations

from alembic import op

revision = "0010"
down_revision = "0009"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.execute("UPDATE sessions SET answer = NULL, answer_version = NULL")


def downgrade() -> None:
    # The old shape ({code, message}) would read the new one, but without the parameters'
    # wording per phone: clear them the same way.
    op.execute("UPDATE sessions SET answer = NULL, answer_version = NULL")
