"""Alembic's entry point: migrate the connection the app hands over (``migrate`` in
``backend/storage/database.py``), or, from the ``alembic`` command line (``alembic revision
--autogenerate -m "..."``), the database of ``BUDDY_DATABASE_URL``."""

from __future__ import annotations

from alembic import context
from sqlalchemy import Connection

from backend.settings import get_settings
from backend.storage.database import connect
from backend.storage.tables import Base


def run(connection: Connection) -> None:
    # Batch mode: SQLite can alter a table only by copying it, which batch operations do.
    context.configure(connection=connection, target_metadata=Base.metadata, render_as_batch=True)
    with context.begin_transaction():
        context.run_migrations()


given: Connection | None = context.config.attributes.get("connection")
if given is not None:
    run(given)
else:
    engine = connect(get_settings().database_url)
    with engine.connect() as connection:
        run(connection)
    engine.dispose()
