"""The two friends alike: roles ``starter`` and ``joiner`` (were seeker and buddy), taps
that say ``friend`` and ``friend_line`` with each tap's precision, the answer stored as each
phone is told it, and the lens of each photo.

Live sessions carry on: roles and taps are rewritten in place (the seeker's ``epipole1``
or ``epipolar_line1`` and the buddy's ``epipole2`` become each one's ``friend`` or
``friend_line``), events name the new roles, and stored answers, whose shape changed, are
cleared: the next read of the state answers again (``backend.sessions.state``).
"""

import json
from typing import Any

import sqlalchemy as sa
from alembic import op

revision, down_revision = "0006", "0005"

NEW_ROLES = {"seeker": "starter", "buddy": "joiner"}
OLD_ROLES = {new: old for old, new in NEW_ROLES.items()}
LENS = {"lens_focal_35mm": sa.Float, "lens_uncertainty": sa.Float, "lens_told_by": sa.String}


def upgrade() -> None:
    _role_length(8)
    _rename_roles(NEW_ROLES, {"result": "answer"})
    _rewrite_taps(_new_taps)
    op.execute("ALTER TABLE sessions RENAME COLUMN result TO answer")
    op.execute("ALTER TABLE sessions RENAME COLUMN result_version TO answer_version")
    op.execute("UPDATE sessions SET answer = NULL, answer_version = NULL")
    for name, kind in LENS.items():
        op.add_column(
            "photos", sa.Column(name, kind(5) if kind is sa.String else kind(), nullable=True)
        )


def downgrade() -> None:
    for name in LENS:
        if op.get_bind().dialect.name == "sqlite":  # SQLite drops a column in place
            op.execute(f"ALTER TABLE photos DROP COLUMN {name}")
        else:
            op.drop_column("photos", name)
    op.execute("ALTER TABLE sessions RENAME COLUMN answer TO result")
    op.execute("ALTER TABLE sessions RENAME COLUMN answer_version TO result_version")
    op.execute("UPDATE sessions SET result = NULL, result_version = NULL")
    _rewrite_taps(_old_taps)
    _rename_roles(OLD_ROLES, {"answer": "result"})
    _role_length(6)


def _rename_roles(roles: dict[str, str], types: dict[str, str]) -> None:
    bind = op.get_bind()
    for old, new in roles.items():
        for table in ("participants", "photos"):
            bind.execute(
                sa.text(f"UPDATE {table} SET role = :new WHERE role = :old"),
                {"new": new, "old": old},
            )
        bind.execute(
            sa.text("UPDATE events SET data = replace(data, :old, :new)"),
            {"old": f'"role": "{old}"', "new": f'"role": "{new}"'},
        )
    for old, new in types.items():
        bind.execute(
            sa.text("UPDATE events SET type = :new WHERE type = :old"), {"new": new, "old": old}
        )


def _rewrite_taps(rewrite: Any) -> None:
    bind = op.get_bind()
    rows = bind.execute(sa.text("SELECT id, role, taps FROM participants WHERE taps IS NOT NULL"))
    for row_id, role, taps in rows.fetchall():
        bind.execute(
            sa.text("UPDATE participants SET taps = :taps WHERE id = :id"),
            {"taps": json.dumps(rewrite(role, json.loads(taps))), "id": row_id},
        )


def _new_taps(role: str, old: dict[str, Any]) -> dict[str, Any]:
    """A seeker's or buddy's taps (roles already renamed) in the friends' words."""
    point = old.get("epipole1") if role == "starter" else old.get("epipole2")
    line = old.get("epipolar_line1") if role == "starter" else None
    return {
        "landmarks": [
            {"id": tap["id"], "x": tap["x"], "y": tap["y"], "sigma": None}
            for tap in old.get("landmarks", [])
        ],
        "friend": None if point is None else {"x": point[0], "y": point[1], "sigma": None},
        "friend_line": (
            None if line is None else {"a": line[0], "b": line[1], "c": line[2], "sigma": None}
        ),
    }


def _old_taps(role: str, new: dict[str, Any]) -> dict[str, Any]:
    """The other way (roles still new): a joiner's line has no old form and is dropped."""
    friend, line = new.get("friend"), new.get("friend_line")
    point = None if friend is None else [friend["x"], friend["y"]]
    starter = role == "starter"
    return {
        "landmarks": [
            {"id": tap["id"], "x": tap["x"], "y": tap["y"]} for tap in new.get("landmarks", [])
        ],
        "epipole1": point if starter else None,
        "epipolar_line1": (
            [line["a"], line["b"], line["c"]] if starter and line and point is None else None
        ),
        "epipole2": None if starter else point,
    }


def _role_length(characters: int) -> None:
    if op.get_bind().dialect.name == "sqlite":  # SQLite does not enforce the length
        return
    for table in ("participants", "photos"):
        op.alter_column(
            table,
            "role",
            type_=sa.String(characters),
            existing_type=sa.String(14 - characters),
            existing_nullable=False,
        )
