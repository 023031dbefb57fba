"""Capability maps under hostile input: robokit's cluster is locked, the chunk store is robokit's
own, allocations are bounded up front, map files are checked before loading, and a scheduler
address cannot hang or blow up the client."""
import io
import os
import resource
import socket
import struct
import subprocess
import sys
import threading
import time
import zipfile
import zlib
from pathlib import Path

import numpy as np
import pytest

import hardening_support as hs

GB = 1024**3


def _limits(mem_bytes):
    """preexec_fn: an address-space limit for the child (a safety net, not a measurement)."""
    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (mem_bytes, mem_bytes))
    return apply


def run_limited(*args, mem=6 * GB, env=None, cwd=None, timeout=hs.HANG_GUARD) -> hs.Run:
    p = subprocess.run([sys.executable, "-m", "robokit.cli", *map(str, args)], capture_output=True, text=True,
                       timeout=timeout, env=env or hs.subprocess_env(), cwd=cwd, preexec_fn=_limits(mem))
    return hs.Run(p.returncode, p.stdout, p.stderr)


# ----------------------------------------------------------------------------- 1. the cluster
def test_own_cluster_refuses_clients_without_its_credentials():
    distributed = pytest.importorskip("distributed")
    pytest.importorskip("cryptography")
    from distributed.security import Security

    from robokit.workspace.capability import _Cluster, capability_map

    with _Cluster(None) as cl:
        addr = cl.client.scheduler.address
        assert addr.startswith("tls://127.0.0.1:")
        psutil = pytest.importorskip("psutil")
        me = psutil.Process()
        listening = [c.laddr for p in [me, *me.children(recursive=True)] for c in p.net_connections("tcp")
                     if c.status == psutil.CONN_LISTEN]
        assert listening and all(a.ip == "127.0.0.1" for a in listening), listening  # no dashboard on 0.0.0.0:8787
        import asyncio
        import ssl

        from distributed.comm import connect

        anyone = ssl.create_default_context(ssl.Purpose.SERVER_AUTH)  # TLS, trusting any server, no client cert
        anyone.check_hostname, anyone.verify_mode = False, ssl.CERT_NONE

        async def identity(address, **kw):
            comm = await connect(address, timeout=5, **kw)
            try:
                await comm.write({"op": "identity"})
                return await asyncio.wait_for(comm.read(), 5)
            finally:
                comm.abort()

        attempts = [(addr, {"ssl_context": anyone}),  # no credentials
                    (addr.replace("tls://", "tcp://"), {}),  # plain TCP
                    (addr, Security.temporary().get_connection_args("client"))]  # someone else's credentials
        for address, kw in attempts:
            with pytest.raises((OSError, TypeError, ValueError, asyncio.TimeoutError)):
                asyncio.run(identity(address, **kw))
        assert asyncio.run(identity(addr, **cl.security.get_connection_args("client")))["type"] == "Scheduler"
        with distributed.Client(addr, security=cl.security, timeout=20) as ours:
            assert ours.submit(sum, [1, 2, 3]).result() == 6
            serial = capability_map("rrr", 0.2, orientations=4, client="serial")
            assert np.array_equal(capability_map("rrr", 0.2, orientations=4, client=ours).index, serial.index)


# ----------------------------------------------------------------------------- 2. the chunk store
STORE_ARGS = ("workspace", "rrr", "--resolution", "0.2", "--orientations", "4", "--scheduler", "serial")


def _ws(tmp_path, main_cli, *extra):
    return main_cli(*STORE_ARGS, "-o", tmp_path / "map.npz", *extra)


def test_users_folder_named_like_the_store_is_left_alone(tmp_path, main_cli):
    mine = tmp_path / "map.npz.chunks"
    mine.mkdir()
    (mine / "thesis.tex").write_text("years of work")
    (mine / "chunk_00000.npz").write_bytes(b"not robokit's")
    run = _ws(tmp_path, main_cli)
    hs.assert_one_line_error(run, "map.npz.chunks", "not a robokit chunk store")
    assert sorted(p.name for p in mine.iterdir()) == ["chunk_00000.npz", "thesis.tex"]
    assert (mine / "thesis.tex").read_text() == "years of work" and not (tmp_path / "map.npz").exists()


def test_store_named_by_a_symlink_is_never_followed(tmp_path, main_cli):
    target = tmp_path / "elsewhere"
    target.mkdir()
    (tmp_path / "map.npz.chunks").symlink_to(target)
    hs.assert_one_line_error(_ws(tmp_path, main_cli), "map.npz.chunks", "symbolic link")
    assert list(target.iterdir()) == [] and (tmp_path / "map.npz.chunks").is_symlink()


def test_store_with_foreign_files_or_linked_chunks_is_refused(tmp_path):
    from robokit.errors import InputError
    from robokit.workspace.store import MARKER, ChunkStore, remove_store

    store = tmp_path / "s"
    with ChunkStore(store) as st:
        st.begin("abc", {}, K=4)
        st.write(0, np.zeros((2, 3)), np.array([1, 2]))
    outside = tmp_path / "outside.npz"
    outside.write_bytes(b"x")
    (store / "chunk_00001.npz").symlink_to(outside)
    with pytest.raises(InputError, match="did not write"):
        ChunkStore(store)
    assert not remove_store(store) and outside.read_bytes() == b"x"
    (store / "chunk_00001.npz").unlink()
    (store / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match=r"did not write \('notes.txt'\)"):
        ChunkStore(store)
    assert not remove_store(store) and (store / "notes.txt").read_text() == "mine"
    (store / "notes.txt").unlink()
    assert remove_store(store) and not store.exists()
    # the marker written by robokit is what makes a folder a store
    (tmp_path / "t").mkdir()
    (tmp_path / "t" / MARKER).mkdir()
    with pytest.raises(InputError, match="robokit-store.json"):
        ChunkStore(tmp_path / "t")


def _corrupt(path: Path, how: str) -> None:
    with np.load(path) as z:
        d = {k: z[k] for k in z.files}
    if how == "negative":
        d["counts"] = d["counts"] - 5
    elif how == "huge":
        d["counts"] = d["counts"] + 10**6
    elif how == "float":
        d["counts"] = d["counts"].astype(float)
    elif how == "short":
        d["counts"] = d["counts"][:-1]
    if how == "garbage":
        path.write_bytes(b"PK\x03\x04garbage")
        return
    buf = io.BytesIO()
    np.savez(buf, **d)
    path.write_bytes(buf.getvalue())


def test_damaged_chunks_are_named_and_recomputed(tmp_path, recwarn):
    from robokit.errors import RobokitWarning
    from robokit.workspace import capability_map

    kw = dict(orientations=4, client="serial", chunk_size=3)
    store = tmp_path / "store"
    first = capability_map("rrr", 0.2, store=store, **kw)
    chunks = sorted(store.glob("chunk_*.npz"))
    hows = ["negative", "huge", "float", "short", "garbage"]
    assert len(chunks) > len(hows)
    for f, how in zip(chunks, hows):
        _corrupt(f, how)
    again = capability_map("rrr", 0.2, store=store, **kw)
    assert np.array_equal(again.index, first.index)  # the map of the damaged store equals the clean one
    assert again.timings["chunks"] == len(hows) and again.timings["chunks_resumed"] == len(chunks) - len(hows)
    notes = [str(w.message) for w in recwarn if issubclass(w.category, RobokitWarning)]
    for f in chunks[:len(hows)]:
        assert any(f.name in n and "recomputing" in n for n in notes), (f.name, notes)
    assert 0 <= again.index.min() and again.index.max() <= 1
    third = capability_map("rrr", 0.2, store=store, **kw)  # and it stays repaired
    assert third.timings["chunks"] == 0


def test_second_run_on_the_same_store_is_refused(tmp_path, main_cli):
    from robokit.workspace.store import ChunkStore

    with ChunkStore(tmp_path / "map.npz.chunks"):  # "another run" holding the store
        hs.assert_one_line_error(_ws(tmp_path, main_cli), "map.npz.chunks", "another robokit run holds")
    assert not (tmp_path / "map.npz").exists()
    assert _ws(tmp_path, main_cli).rc == 0  # released: the next run works and removes the store
    assert (tmp_path / "map.npz").is_file() and not (tmp_path / "map.npz.chunks").exists()


# ----------------------------------------------------------------------------- 3. bounded allocation
@pytest.mark.parametrize("args, words", [
    (["--orientations", "1000000000", "--resolution", "0.2"], ["orientations", "GB"]),
    (["--orientations", "100000000", "--resolution", "0.2"], ["orientations", "GB"]),
    (["--orientations", "10", "--resolution", "0.0004"], ["resolution", "GB"]),
])
def test_huge_maps_are_refused_up_front(args, words, tmp_path):
    """--orientations 10⁹ / 10⁸ and a very fine grid: one line with the memory it would need,
    under a 6 GB address-space limit (the old code asked for 72 GB, 7 GB, …)."""
    run = run_limited("workspace", "puma560", *args, "--scheduler", "serial", "-o", tmp_path / "m.npz")
    hs.assert_one_line_error(run, *words, "refuses maps above")
    assert list(tmp_path.iterdir()) == []


# ----------------------------------------------------------------------------- 4. map files
def _npy(arr) -> bytes:
    buf = io.BytesIO()
    np.lib.format.write_array(buf, np.asanyarray(arr), allow_pickle=True)
    return buf.getvalue()


def _header_only(shape, dtype="<f8") -> bytes:
    """A .npy whose header declares ``shape`` but which holds no data."""
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": dtype, "fortran_order": False, "shape": shape})
    return buf.getvalue()


GOOD = dict(centres=np.array([[0.1, 0.2, 0.3], [0.2, 0.2, 0.3]]), index=np.array([0.5, 1.0]),
            orientations=np.stack([np.eye(3), np.diag([1.0, -1.0, -1.0])]), resolution=np.float64(0.1))


def _zip(members: dict, compress=zipfile.ZIP_STORED, extra=()) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compress) as z:
        for name, data in list(members.items()) + list(extra):
            z.writestr(name if name.endswith(".npy") or "/" in name else name + ".npy",
                       data if isinstance(data, bytes) else _npy(data))
    return buf.getvalue()


def _with(**changes):
    m = dict(GOOD)
    m.update(changes)
    return {k: v for k, v in m.items() if v is not None}


def _declared_size_bomb() -> bytes:
    """A tiny zip whose directory says centres.npy expands to 3.6 GB (sizes patched in)."""
    data = _zip(_with(), zipfile.ZIP_DEFLATED)
    raw = bytearray(data)
    huge = struct.pack("<I", 3_600_000_000)
    name = b"centres.npy"
    lh = raw.find(b"PK\x03\x04")  # the local headers
    while lh >= 0:
        n = struct.unpack_from("<H", raw, lh + 26)[0]
        if raw[lh + 30:lh + 30 + n] == name:
            raw[lh + 22:lh + 26] = huge
        lh = raw.find(b"PK\x03\x04", lh + 4)
    ch = raw.find(b"PK\x01\x02")
    while ch >= 0:
        n = struct.unpack_from("<H", raw, ch + 28)[0]
        if raw[ch + 46:ch + 46 + n] == name:
            raw[ch + 24:ch + 28] = huge
        ch = raw.find(b"PK\x01\x02", ch + 4)
    return bytes(raw)


def _ratio_bomb() -> bytes:
    """A real deflate bomb: 64 MB of zeros as index.npy, about 64 kB compressed."""
    zeros = np.zeros(8 * 1024**2)
    return _zip(_with(index=zeros, centres=np.zeros((len(zeros), 3))[:0].reshape(0, 3)), zipfile.ZIP_DEFLATED)


HOSTILE_MAPS = {
    "huge-header": (lambda: _zip(_with(centres=_header_only((10**11, 3)))), "centres"),
    "declared-3.6GB": (_declared_size_bomb, "centres"),
    "deflate-bomb": (_ratio_bomb, "index"),
    "object-dtype": (lambda: _zip(_with(index=np.array([{"a": 1}, None], dtype=object))), "index"),
    "complex": (lambda: _zip(_with(index=np.array([0.5 + 1j, 1.0]))), "index"),
    "text-centres": (lambda: _zip(_with(centres=np.array([["a", "b", "c"]] * 2))), "centres"),
    "nan-centres": (lambda: _zip(_with(centres=np.array([[np.nan, 0, 0], [0, 0, 0]]))), "centres"),
    "inf-index": (lambda: _zip(_with(index=np.array([np.inf, 1.0]))), "index"),
    "index-above-1": (lambda: _zip(_with(index=np.array([1.5, 1.0]))), "index"),
    "negative-index": (lambda: _zip(_with(index=np.array([-0.1, 1.0]))), "index"),
    "index-count": (lambda: _zip(_with(index=np.array([0.5]))), "index"),
    "negative-resolution": (lambda: _zip(_with(resolution=np.float64(-0.1))), "resolution"),
    "nan-resolution": (lambda: _zip(_with(resolution=np.float64(np.nan))), "resolution"),
    "array-resolution": (lambda: _zip(_with(resolution=np.array([0.1, 0.2]))), "resolution"),
    "centres-2d": (lambda: _zip(_with(centres=np.zeros((2, 2)))), "centres"),
    "orientations-shape": (lambda: _zip(_with(orientations=np.zeros((2, 3)))), "orientations"),
    "not-rotations": (lambda: _zip(_with(orientations=np.stack([2 * np.eye(3)] * 2))), "orientations"),
    "reflection": (lambda: _zip(_with(orientations=np.stack([-np.eye(3)] * 2))), "orientations"),
    "no-orientations": (lambda: _zip(_with(orientations=np.zeros((0, 3, 3)))), "orientations"),
    "missing-member": (lambda: _zip(_with(index=None)), "index"),
    "duplicate-member": (lambda: _zip(_with(), extra=[("index.npy", _npy(np.array([0.0, 0.0])))]), "index.npy"),
    "dotdot-member": (lambda: _zip(_with(), extra=[("a/../centres.npy", _npy(np.zeros((2, 3))))]), "a/../centres.npy"),
    "fortran-mismatch": (lambda: _zip(_with(centres=_npy(np.zeros((2, 3)))[:-8])), "centres"),
    "not-a-zip": (lambda: b"\x93NUMPY nonsense", "npz"),
    "truncated": (lambda: _zip(_with())[:200], "npz"),
    "long-robot-name": (lambda: _zip(_with(robot=np.str_("r" * 20000))), "robot"),
}


@pytest.fixture(scope="module")
def hostile_maps(tmp_path_factory):
    import warnings

    folder = tmp_path_factory.mktemp("maps")
    paths = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # zipfile warns about the duplicate name
        for name, (make, _) in HOSTILE_MAPS.items():
            paths[name] = folder / f"{name}.npz"
            paths[name].write_bytes(make())
    return paths


@pytest.mark.parametrize("case", sorted(HOSTILE_MAPS))
def test_hostile_map_file_is_refused_before_loading(case, hostile_maps, tmp_path):
    from robokit.errors import InputError
    from robokit.workspace import CapabilityMap

    path = hostile_maps[case]
    with pytest.raises(InputError) as err:
        CapabilityMap.load(path)
    msg = str(err.value)
    assert str(path) in msg and HOSTILE_MAPS[case][1] in msg and len(msg) < 400, msg


def test_hostile_maps_through_the_cli_in_bounded_memory(hostile_maps, tmp_path):
    """``robokit view MAP.npz``: exit 2, one line naming the file, nothing written, under a 3 GB
    address-space limit (the old code allocated the header's 2.4 TB or the bomb's 3.6 GB)."""
    for case in ("huge-header", "declared-3.6GB"):
        out = tmp_path / f"{case}.html"
        run = run_limited("view", hostile_maps[case], "-o", out, mem=3 * GB)
        hs.assert_one_line_error(run, hostile_maps[case].name)
        assert not out.exists()


def test_map_file_links_fifos_and_folders_are_refused(tmp_path, main_cli):
    from robokit.workspace import capability_map

    good = tmp_path / "good.npz"
    capability_map("rrr", 0.2, orientations=4, client="serial").save(good)
    link = tmp_path / "link.npz"
    link.symlink_to(good)
    fifo = tmp_path / "fifo.npz"
    os.mkfifo(fifo)
    folder = tmp_path / "folder.npz"
    folder.mkdir()
    for path, word in ((link, "symbolic link"), (fifo, "not a regular file"), (folder, "not a regular file"),
                       (tmp_path / "missing.npz", "not found")):
        run = main_cli("view", path, "-o", tmp_path / "out.html")
        hs.assert_one_line_error(run, path.name, word)
    assert not (tmp_path / "out.html").exists()
    assert main_cli("view", good, "-o", tmp_path / "out.html").rc == 0  # the file itself is fine


def test_a_compressed_map_robokit_did_not_write_still_loads(tmp_path):
    from robokit.workspace import CapabilityMap

    p = tmp_path / "c.npz"
    np.savez_compressed(p, **GOOD)
    m = CapabilityMap.load(p)
    assert np.array_equal(m.index, GOOD["index"]) and m.resolution == 0.1


# ----------------------------------------------------------------------------- 5. --scheduler
class _Server:
    """A 127.0.0.1 server that accepts and then stays silent, or sends ``reply``; it stops by
    itself after ``life`` seconds."""

    def __init__(self, reply: bytes | None, life: float = 40.0):
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.sock.settimeout(0.2)
        self.port = self.sock.getsockname()[1]
        self.reply, self.deadline, self.conns = reply, time.monotonic() + life, []
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        try:
            while time.monotonic() < self.deadline:
                try:
                    c, _ = self.sock.accept()
                except socket.timeout:
                    continue
                self.conns.append(c)
                if self.reply is not None:
                    try:
                        c.sendall(self.reply)
                    except OSError:
                        pass
        finally:
            for c in self.conns:
                c.close()
            self.sock.close()

    def stop(self):
        self.deadline = 0
        self.thread.join(5)


@pytest.mark.parametrize("reply, word", [
    (None, "did not answer"),
    (struct.pack("<Q", 6 * 10**9) + b"\x00" * 64, "not a Dask scheduler"),
    (b"HTTP/1.1 200 OK\r\n\r\nhello", "not a Dask scheduler"),
], ids=["silent", "6GB-length-prefix", "http"])
def test_scheduler_that_hangs_or_lies_is_refused(reply, word, tmp_path):
    server = _Server(reply)
    try:
        t0 = time.monotonic()
        run = run_limited("workspace", "rrr", "--resolution", "0.2", "--scheduler", f"tcp://127.0.0.1:{server.port}",
                          "-o", tmp_path / "m.npz", mem=3 * GB,
                          env=hs.subprocess_env(DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT="2s"))
        hs.assert_one_line_error(run, f"127.0.0.1:{server.port}", word)
        assert time.monotonic() - t0 < hs.HANG_GUARD
        assert not (tmp_path / "m.npz").exists() and not (tmp_path / "m.npz.chunks").exists()
    finally:
        server.stop()


def test_scheduler_probe_accepts_a_real_scheduler():
    distributed = pytest.importorskip("distributed")
    from robokit.workspace.cluster import probe_scheduler

    with distributed.LocalCluster(n_workers=0, processes=False, protocol="tcp://", host="127.0.0.1",
                                  scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"}) as lc:
        probe_scheduler(lc.scheduler_address, timeout=10)  # no exception: a Dask frame of sane size
