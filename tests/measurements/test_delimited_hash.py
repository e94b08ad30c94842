"""The file's SHA-256, hashed in a thread beside the parsing of a large table (readers/
_delimited._hashing, issue 31), is the hash of all its bytes; a failure of that thread is
raised where the hash is asked for, not lost."""

import hashlib

import pytest

from contactres.measurements.readers import _delimited

ROWS = (f"s{i // 12},{i}e-10,{i / 7:.6g}\n" for i in range(600))
TABLE = "sweep,amplitude_m,df_Hz\n" + "".join(ROWS)


@pytest.mark.parametrize("beside", [0, 1 << 30])  # in a thread, in the caller's
def test_the_hash_is_the_files(tmp_path, monkeypatch, beside):
    path = tmp_path / "table.csv"
    path.write_bytes(b"\xef\xbb\xbf" + TABLE.encode())  # the byte order mark hashed too
    want = hashlib.sha256(path.read_bytes()).hexdigest()
    monkeypatch.setattr(_delimited, "_HASHED_BESIDE", beside)
    assert _delimited.load(path, ("amplitude_m", "df_Hz")).attrs["sha256"] == want


def test_a_failure_of_the_hashing_thread_is_raised_where_the_hash_is_asked(monkeypatch):
    monkeypatch.setattr(_delimited, "_HASHED_BESIDE", 0)
    digest = _delimited._hashing("not bytes")  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        digest()


def test_where_no_thread_starts_the_hash_is_taken_here(tmp_path, monkeypatch):
    # (a limit on threads: review R30c) the reading goes on, with the same digest
    def refuse(self):
        raise RuntimeError("can't start new thread")

    monkeypatch.setattr(_delimited, "_HASHED_BESIDE", 0)
    monkeypatch.setattr(_delimited.threading.Thread, "start", refuse)
    path = tmp_path / "table.csv"
    path.write_text(TABLE, encoding="utf-8")
    want = hashlib.sha256(path.read_bytes()).hexdigest()
    assert _delimited.load(path, ("amplitude_m", "df_Hz")).attrs["sha256"] == want
    with pytest.raises(TypeError):
        _delimited._hashing("not bytes")()  # type: ignore[arg-type]
