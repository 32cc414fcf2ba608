"""How long the erase (``VACUUM FULL``) holds a table of photos, by how photo bytes are kept.

PostgreSQL erases deleted rows' bytes from its files only by copying the table (the app's
sweeper runs ``VACUUM (FULL)``), and locks the table meanwhile. This times it on a table of
``--photos`` phone photos (the load benchmark's, 2560 px), a quarter of them deleted, once
with PostgreSQL's default storage for bytea (EXTENDED: a compression try for each value, at
the insert and again at the copy) and once as migration 0007 keeps photos (EXTERNAL: none),
on a throwaway server (``deploy/postgres.py``). Also the insert's PostgreSQL CPU per photo.

    .venv/bin/python benchmarks/erase.py [--photos N]
"""

from __future__ import annotations

import argparse
import time

import psutil
import psycopg
from crowd import Crowd

from deploy.postgres import PostgresServer


def measure(connection: psycopg.Connection, storage: str, photos: list[bytes]) -> str:
    connection.execute("DROP TABLE IF EXISTS photos_timed")
    connection.execute("CREATE TABLE photos_timed (id serial PRIMARY KEY, data bytea)")
    connection.execute(f"ALTER TABLE photos_timed ALTER COLUMN data SET STORAGE {storage}")
    backend = psutil.Process(int(connection.info.backend_pid))
    cpu = sum(backend.cpu_times()[:2])
    for photo in photos:
        connection.execute("INSERT INTO photos_timed (data) VALUES (%s)", (photo,))
    insert_ms = 1000 * (sum(backend.cpu_times()[:2]) - cpu) / len(photos)
    connection.execute("DELETE FROM photos_timed WHERE id % 4 = 0")
    size = connection.execute("SELECT pg_total_relation_size('photos_timed')").fetchone()
    megabytes = (size[0] if size else 0) / 2**20
    started = time.perf_counter()
    connection.execute("VACUUM (FULL) photos_timed")
    seconds = time.perf_counter() - started
    return (
        f"| {storage} | {megabytes:.0f} MB | {seconds:.2f} s | {100 * seconds / megabytes:.2f} s"
        f" | {insert_ms:.1f} ms |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument("--photos", type=int, default=200, help="photos inserted (%(default)s)")
    args = parser.parse_args()
    crowd = Crowd.made(2560, seed=1)
    photos = [crowd.photos[n % 2] for n in range(args.photos)]
    server = PostgresServer()
    try:
        server.start()
        url = server.url(server.create_database()).replace("postgresql+psycopg", "postgresql")
        with psycopg.connect(url, autocommit=True) as connection:
            sizes = " and ".join(f"{len(photo) // 1000} KB" for photo in crowd.photos)
            print(f"`python benchmarks/erase.py --photos {args.photos}`: VACUUM FULL of a table")
            print(f"of {args.photos} photos ({sizes}), a quarter of them deleted first.\n")
            print("| storage | table | VACUUM FULL | per 100 MB | insert, PostgreSQL CPU |")
            print("|---|---|---|---|---|")
            for storage in ("EXTENDED", "EXTERNAL"):
                print(measure(connection, storage, photos))
    finally:
        server.remove()


if __name__ == "__main__":
    main()
