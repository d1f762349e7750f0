#!/usr/bin/env python3
"""Checks an MCAP file with MCAP's own Python library (PyPI `mcap`), as far as
the library allows what the Go CLI's `mcap doctor` and `mcap info` do (that
CLI is not installable here: docs/logging.md).

    mcap_py_check.py FILE.mcap [--expect-cut]

Every record is parsed by the library (mcap.stream_reader.StreamReader,
validate_crcs=True: the chunks' CRCs and the data section's CRC in DataEnd);
this script only compares what it parsed:

  - each record, written again by the library's own record classes, is the
    same bytes as in the file (so an attachment's CRC is the one the library
    computes, and no record carries bytes the library does not know);
  - every chunk decompressed (zstd, by the library): its CRC, its messages'
    channels known, its message_start/end_time the messages' min and max;
    the MessageIndex records after it hold exactly its messages' (log_time,
    offset) per channel, sorted by log time;
  - the summary: every Schema and Channel as in the data section, the
    Statistics (message, schema, channel, attachment, metadata and chunk
    counts, start and end times, per-channel counts) equal to what the
    messages and records found, one ChunkIndex per chunk with its fields
    (offset, lengths, message index offsets and length, compression, sizes,
    times), one AttachmentIndex and MetadataIndex per record with theirs,
    the SummaryOffset records each covering its group exactly, the footer's
    summary_start, summary_offset_start and summary CRC;
  - then the library's indexed reader (mcap.reader.make_reader on the file,
    SeekingReader, validate_crcs=True) reads every message through the chunk
    indexes in log-time order, and decodes each with the schema the file
    carries (message encoding json: strict JSON, no NaN; schema encoding
    jsonschema: validated by the `jsonschema` package, the validator the
    schema's $schema names; `record --raw`'s channels lcm/..., encoding lcm
    without a schema, are read, not decoded); its counts per topic equal
    the linear read's;
    its attachments and metadata records are read back by name.

A cut file (a recorder killed with SIGKILL: no DataEnd, summary or footer)
fails unless --expect-cut is given. With it, the file is read as a stream
(the library's NonSeekingReader and StreamReader, no index): every whole
record must be sound, as above; a record cut by the end of the file is what
a reader cannot have and is named, not a failure; the indexed reader's
refusal is reported. A cut file that turns out complete fails --expect-cut.

Prints a JSON report on stdout (counts and log times per topic, the
records, the problems) and a summary on stderr. Exit 0: no problem;
1: problems (listed); 2: the file cannot be opened; 77: the `mcap` or
`jsonschema` package is missing ("SKIP: ..."), run scripts/setup-python.sh.
"""

import io
import json
import os
import struct
import sys
import zlib

try:
    from importlib.metadata import version

    import jsonschema
    from mcap.data_stream import RecordBuilder
    from mcap.decoder import DecoderFactory
    from mcap.exceptions import EndOfFile
    from mcap.opcode import Opcode
    from mcap.reader import NonSeekingReader, make_reader
    from mcap.records import (
        Attachment,
        AttachmentIndex,
        Channel,
        Chunk,
        ChunkIndex,
        DataEnd,
        Footer,
        Header,
        Message,
        MessageIndex,
        Metadata,
        MetadataIndex,
        Schema,
        Statistics,
        SummaryOffset,
    )
    from mcap.stream_reader import StreamReader, get_chunk_data_stream
except ImportError as e:
    print(
        f"SKIP: mcap_py_check.py needs the Python packages mcap and jsonschema ({e}; "
        f"interpreter {sys.executable}): run scripts/setup-python.sh",
        file=sys.stderr,
    )
    sys.exit(77)

MAX_LISTED = 20  # problems of one kind listed; the rest counted


class Problems:
    def __init__(self):
        self.items, self.kinds = [], {}

    def add(self, kind, text):
        n = self.kinds.get(kind, 0)
        self.kinds[kind] = n + 1
        if n < MAX_LISTED:
            self.items.append(f"{kind}: {text}")
        elif n == MAX_LISTED:
            self.items.append(f"{kind}: more (counted in problem_counts)")


def record_bytes(record):
    """the record as the library writes it (opcode, length, content)"""
    b = RecordBuilder()
    record.write(b)
    return b.end()


RAW = object()  # a raw LCM message: read, not decoded


def reject_constant(name):
    raise ValueError(f"{name} is not JSON")


class JsonSchemaDecoders(DecoderFactory):
    """message encoding json with a jsonschema schema: the decoded value, or
    the reason it is not valid, per message (mcap's decoder mechanism)"""

    def __init__(self, problems):
        self.problems = problems

    def decoder_for(self, message_encoding, schema):
        if message_encoding == "lcm" and schema is None:
            # `record --raw`: the LCM bytes as published (channels lcm/...),
            # self-describing to LCM tools only: kept, not decoded
            return lambda data: (RAW, None)
        if message_encoding != "json":
            return None
        if schema is None:  # a schemaless channel: JSON only
            validator = None
        else:
            if schema.encoding != "jsonschema":
                return None
            try:
                s = json.loads(schema.data.decode("utf-8"), parse_constant=reject_constant)
                cls = jsonschema.validators.validator_for(s)
                cls.check_schema(s)
                validator = cls(s)
            except Exception as e:  # noqa: BLE001: any reason the schema is unusable
                self.problems.add("schema", f"{schema.name} (id {schema.id}) is not a valid JSON Schema: {e}")
                validator = None

        def decode(data):
            try:
                value = json.loads(data.decode("utf-8"), parse_constant=reject_constant)
            except (UnicodeDecodeError, ValueError) as e:
                return None, f"not JSON: {e}"
            if validator is not None and not validator.is_valid(value):
                err = jsonschema.exceptions.best_match(validator.iter_errors(value))
                return None, f"does not validate: {err.message} at {'/'.join(map(str, err.absolute_path))}"
            return value, None

        return decode


class Linear:
    """every record of the file in order, by the library's StreamReader, with
    each record's offset and length (the file's position between records)"""

    def __init__(self, path, problems):
        self.path, self.problems = path, problems
        self.size = os.path.getsize(path)
        self.header = None
        self.schemas, self.channels = {}, {}  # id -> record, from the data section
        self.chunks = []  # dicts: offset, length, chunk, entries (channel -> (log_time, offset)), index_records
        self.attachments, self.metadata = [], []  # (offset, length, record)
        self.messages = 0
        self.topic_counts, self.topic_times = {}, {}
        self.channel_counts = {}
        self.sequences = {}  # topic -> the Message records' sequence fields
        self.start = self.end = None
        self.data_end = None  # (offset, record)
        self.summary = []  # (offset, length, record) after DataEnd, before the footer
        self.footer = None  # (offset, record)
        self.cut = None  # text: where the file ends inside a record
        self.broken = None  # text: the whole record the stream reader stopped at
        self.records = 0

    def run(self):
        with open(self.path, "rb") as f:
            fd = f.fileno()
            reader = StreamReader(f, emit_chunks=True, validate_crcs=True)
            records = reader.records
            while True:
                at = f.tell() or 8  # (the first record follows the magic the reader checks first)
                try:
                    record = next(records)
                except StopIteration:
                    break
                except Exception as e:  # noqa: BLE001: EndOfFile, struct.error, McapError, CRC errors (ValueError)
                    self._stopped(fd, e)
                    break
                end = f.tell()
                self.records += 1
                try:
                    self._record(fd, at, end, record)
                except Exception as e:  # noqa: BLE001: a record the library read but that does not parse further
                    self.problems.add("record", f"{type(record).__name__} at offset {at}: {type(e).__name__}: {e}")

    def _stopped(self, fd, error):
        """the stream reader stopped: at a record cut by the end of the file,
        or at a corrupt one (then this is a problem)"""
        # the record that failed begins at the end of the last one read
        start = self._last_end
        prefix = os.pread(fd, 9, start)
        if not prefix:
            self.cut = f"the file ends after the whole record ending at offset {start}"
            return
        if len(prefix) < 9:
            self.cut = f"the file ends {len(prefix)} bytes into a record's opcode and length at offset {start}"
            return
        opcode, length = struct.unpack("<BQ", prefix)
        name = Opcode(opcode).name if opcode in Opcode._value2member_map_ else f"opcode {opcode:#x}"
        if start + 9 + length > self.size:
            self.cut = (
                f"a {name} record of {9 + length} bytes at offset {start} is cut by the end of the file "
                f"({self.size - start} bytes of it present)"
            )
        else:
            self.broken = f"the stream reader stopped at the {name} record at offset {start} ({9 + length} bytes, whole)"
            self.problems.add("record", f"{self.broken}: {type(error).__name__}: {error}")

    _last_end = 8
    _previous = None  # the record before this one (message indexes follow their chunk)

    def _record(self, fd, at, end, record):
        try:
            self._record_checked(fd, at, end, record)
        finally:
            self._last_end, self._previous = end, record

    def _record_checked(self, fd, at, end, record):
        raw = os.pread(fd, end - at, at)
        again = b"" if isinstance(record, Chunk) else record_bytes(record)  # (a chunk: _chunk)
        if isinstance(record, Attachment) and again[:-4] == raw[:-4] and again[-4:] != raw[-4:]:
            self.problems.add(
                "crc",
                f"Attachment {record.name!r} at offset {at}: CRC {raw[-4:][::-1].hex()}, "
                f"the library computes {again[-4:][::-1].hex()}",
            )
        elif again and again != raw:
            self.problems.add(
                "record bytes",
                f"{type(record).__name__} at offset {at}: the library writes what it read differently "
                f"({len(again)} bytes against {len(raw)} in the file)",
            )
        after_data_end = self.data_end is not None
        if isinstance(record, Header):
            if self.header is not None or at != 8:
                self.problems.add("layout", f"Header at offset {at}: only one, right after the magic")
            self.header = record
            return
        if self.header is None:
            self.problems.add("layout", f"{type(record).__name__} at offset {at} before the Header")
        if isinstance(record, Footer):
            self.footer = (at, record)
            return
        if after_data_end:
            self.summary.append((at, end - at, record))
            return
        if isinstance(record, DataEnd):
            self.data_end = (at, record)
        elif isinstance(record, Schema):
            self._schema(at, record)
        elif isinstance(record, Channel):
            self._channel(at, record)
        elif isinstance(record, Chunk):
            self._chunk(at, end - at, record, raw)
        elif isinstance(record, MessageIndex):
            self._message_index(at, end - at, record)
        elif isinstance(record, Message):
            self.problems.add("layout", f"a Message at offset {at} outside chunks (this writer chunks every message)")
            self._message(record)
        elif isinstance(record, Attachment):
            self.attachments.append((at, end - at, record))
        elif isinstance(record, Metadata):
            self.metadata.append((at, end - at, record))
        else:
            self.problems.add("layout", f"{type(record).__name__} at offset {at} in the data section")

    def _schema(self, at, s):
        if s.id == 0:
            self.problems.add("schema", f"Schema at offset {at} has id 0 (reserved: no schema)")
        old = self.schemas.get(s.id)
        if old is not None and old != s:
            self.problems.add("schema", f"Schema id {s.id} at offset {at} differs from an earlier one")
        self.schemas[s.id] = s

    def _channel(self, at, c):
        if c.schema_id != 0 and c.schema_id not in self.schemas:
            self.problems.add("channel", f"Channel {c.id} ({c.topic}) at offset {at}: schema {c.schema_id} not yet defined")
        old = self.channels.get(c.id)
        if old is not None and old != c:
            self.problems.add("channel", f"Channel id {c.id} at offset {at} differs from an earlier one")
        self.channels[c.id] = c

    def _message(self, m):
        c = self.channels.get(m.channel_id)
        if c is None:
            self.problems.add("message", f"a message on unknown channel {m.channel_id}")
            return
        self.messages += 1
        self.channel_counts[m.channel_id] = self.channel_counts.get(m.channel_id, 0) + 1
        self.topic_counts[c.topic] = self.topic_counts.get(c.topic, 0) + 1
        self.sequences.setdefault(c.topic, []).append(m.sequence)
        t0, t1 = self.topic_times.get(c.topic, (m.log_time, m.log_time))
        self.topic_times[c.topic] = (min(t0, m.log_time), max(t1, m.log_time))
        self.start = m.log_time if self.start is None else min(self.start, m.log_time)
        self.end = m.log_time if self.end is None else max(self.end, m.log_time)

    def _chunk(self, at, length, chunk, raw):
        if record_bytes(chunk) != raw:
            self.problems.add("record bytes", f"Chunk at offset {at}: the library writes it differently")
        entry = {"offset": at, "length": length, "chunk": chunk, "entries": {}, "index_records": None}
        self.chunks.append(entry)
        if chunk.compression not in ("", "zstd", "lz4"):
            self.problems.add("chunk", f"chunk at offset {at}: unknown compression {chunk.compression!r}")
            return
        try:  # decompressed by the library, its CRC checked
            stream, n = get_chunk_data_stream(chunk, validate_crc=True)
        except Exception as e:  # noqa: BLE001: zstd errors, CRC mismatches
            self.problems.add("chunk", f"chunk at offset {at}: {type(e).__name__}: {e}")
            return
        if n != chunk.uncompressed_size:
            self.problems.add("chunk", f"chunk at offset {at}: {n} bytes decompressed, it says {chunk.uncompressed_size}")
        if chunk.uncompressed_crc == 0:
            self.problems.add("chunk", f"chunk at offset {at}: no CRC (0)")
        lo = hi = None
        try:
            while stream.count < n:
                offset = stream.count
                opcode, rlen = stream.read1(), stream.read8()
                if offset + 9 + rlen > n:
                    self.problems.add("chunk", f"chunk at offset {at}: a record at {offset} runs past its end")
                    break
                if opcode == Opcode.MESSAGE:
                    m = Message.read(stream, rlen)
                    self._message(m)
                    entry["entries"].setdefault(m.channel_id, []).append((m.log_time, offset))
                    lo = m.log_time if lo is None else min(lo, m.log_time)
                    hi = m.log_time if hi is None else max(hi, m.log_time)
                elif opcode == Opcode.SCHEMA:
                    self._schema(at, Schema.read(stream))
                elif opcode == Opcode.CHANNEL:
                    self._channel(at, Channel.read(stream))
                else:
                    self.problems.add("chunk", f"chunk at offset {at}: a {opcode:#x} record inside it")
                    stream.read(rlen)
                if stream.count != offset + 9 + rlen:
                    self.problems.add("chunk", f"chunk at offset {at}: the record at {offset} is not {rlen} bytes long")
                    break
        except (EndOfFile, struct.error) as e:
            self.problems.add("chunk", f"chunk at offset {at}: its records end inside one: {e}")
        if lo is None:
            self.problems.add("chunk", f"chunk at offset {at} holds no message")
        elif (lo, hi) != (chunk.message_start_time, chunk.message_end_time):
            self.problems.add(
                "chunk",
                f"chunk at offset {at}: says log times {chunk.message_start_time}..{chunk.message_end_time}, "
                f"its messages {lo}..{hi}",
            )

    def _message_index(self, at, length, mi):
        if not isinstance(self._previous, (Chunk, MessageIndex)):
            self.problems.add("message index", f"MessageIndex at offset {at} does not follow a chunk")
            return
        chunk = self.chunks[-1]
        if chunk["index_records"] is None:
            chunk["index_records"] = []
        chunk["index_records"].append((at, length, mi))
        want = sorted(chunk["entries"].get(mi.channel_id, []), key=lambda e: e[0])
        if mi.records != want:
            if sorted(mi.records) == sorted(want):
                self.problems.add("message index", f"MessageIndex at offset {at} (channel {mi.channel_id}): not sorted by log time")
            else:
                self.problems.add(
                    "message index",
                    f"MessageIndex at offset {at} (channel {mi.channel_id}): {len(mi.records)} entries, the chunk at "
                    f"offset {chunk['offset']} holds {len(want)} messages of that channel"
                    + ("" if len(mi.records) != len(want) else " at other log times or offsets"),
                )

    def end_of_chunk_indexes(self):
        """after the linear read: every chunk's message indexes name each of its
        channels once"""
        for i, c in enumerate(self.chunks):
            recs = c["index_records"] or []
            named = [mi.channel_id for _, _, mi in recs]
            if len(named) != len(set(named)):
                self.problems.add("message index", f"chunk at offset {c['offset']}: a channel indexed twice")
            missing = set(c["entries"]) - set(named)
            last = i == len(self.chunks) - 1
            if missing and not (last and self.cut):
                self.problems.add(
                    "message index", f"chunk at offset {c['offset']}: no MessageIndex for channels {sorted(missing)}"
                )


def check_summary(lin, problems, path):
    """the summary section and footer against what the linear read found"""
    if lin.data_end is None:
        problems.add("layout", "no DataEnd record")
    elif lin.data_end[1].data_section_crc == 0:
        problems.add("crc", "DataEnd's data_section_crc is 0 (not checked)")
    if lin.footer is None:
        problems.add("layout", "no Footer")
        return None
    footer_at, footer = lin.footer
    summary = lin.summary
    first = summary[0][0] if summary else None
    if not summary:
        problems.add("summary", "the footer has no summary (summary_start 0): readers cannot index the file")
        if footer.summary_start != 0:
            problems.add("summary", f"footer summary_start {footer.summary_start} but no summary records")
        return None
    if footer.summary_start != first:
        problems.add("summary", f"footer summary_start {footer.summary_start}, the summary begins at {first}")
    offsets = [(a, n, r) for a, n, r in summary if isinstance(r, SummaryOffset)]
    want_so = offsets[0][0] if offsets else 0
    if footer.summary_offset_start != want_so:
        problems.add("summary", f"footer summary_offset_start {footer.summary_offset_start}, the SummaryOffsets begin at {want_so}")
    if offsets and any(not isinstance(r, SummaryOffset) for a, _, r in summary if a > want_so):
        problems.add("summary", "records after the SummaryOffset records")
    with open(path, "rb") as f:
        covered = os.pread(f.fileno(), footer_at + 9 + 16 - footer.summary_start, footer.summary_start)
    if footer.summary_crc == 0:
        problems.add("crc", "the footer's summary_crc is 0 (not checked)")
    elif zlib.crc32(covered) != footer.summary_crc:
        problems.add("crc", f"summary CRC {footer.summary_crc:#x}, computed {zlib.crc32(covered):#x}")

    # the summary offsets: each group exactly the records of its opcode
    records = [(a, n, r) for a, n, r in summary if not isinstance(r, SummaryOffset)]
    for a, n, so in offsets:
        group = [(ra, rn, r) for ra, rn, r in records if so.group_start <= ra < so.group_start + so.group_length]
        kinds = {type(r).__name__ for _, _, r in group}
        try:
            op = Opcode(so.group_opcode)
        except ValueError:
            problems.add("summary offset", f"SummaryOffset at {a}: unknown opcode {so.group_opcode:#x}")
            continue
        all_of_op = [(ra, rn) for ra, rn, r in records if record_opcode(r) == op]
        if (
            not group
            or group[0][0] != so.group_start
            or sum(rn for _, rn, _ in group) != so.group_length
            or any(record_opcode(r) != op for _, _, r in group)
            or [(ra, rn) for ra, rn, _ in group] != all_of_op
        ):
            problems.add(
                "summary offset",
                f"SummaryOffset at {a} for {op.name} ({so.group_start}, {so.group_length} bytes) does not cover "
                f"exactly its group (found {sorted(kinds)})",
            )
    grouped = {Opcode(so.group_opcode) for _, _, so in offsets if so.group_opcode in Opcode._value2member_map_}
    for op in {record_opcode(r) for _, _, r in records} - grouped:
        problems.add("summary offset", f"no SummaryOffset for the {op.name} records of the summary")

    sum_schemas = {r.id: r for _, _, r in records if isinstance(r, Schema)}
    sum_channels = {r.id: r for _, _, r in records if isinstance(r, Channel)}
    if sum_schemas != lin.schemas:
        problems.add("summary", f"the summary's schemas {sorted(sum_schemas)} differ from the data section's {sorted(lin.schemas)}")
    if sum_channels != lin.channels:
        problems.add("summary", f"the summary's channels {sorted(sum_channels)} differ from the data section's {sorted(lin.channels)}")

    stats = [r for _, _, r in records if isinstance(r, Statistics)]
    if len(stats) != 1:
        problems.add("statistics", f"{len(stats)} Statistics records in the summary")
    else:
        s = stats[0]
        want = {
            "message_count": lin.messages,
            "schema_count": len(lin.schemas),
            "channel_count": len(lin.channels),
            "attachment_count": len(lin.attachments),
            "metadata_count": len(lin.metadata),
            "chunk_count": len(lin.chunks),
            "message_start_time": lin.start or 0,
            "message_end_time": lin.end or 0,
            "channel_message_counts": dict(sorted(lin.channel_counts.items())),
        }
        for k, v in want.items():
            got = getattr(s, k)
            if k == "channel_message_counts":
                got = {c: n for c, n in sorted(got.items()) if n}  # channels without messages may be listed as 0
            if got != v:
                problems.add("statistics", f"{k} {got}, the file holds {v}")

    by_offset = {c["offset"]: c for c in lin.chunks}
    indexed = set()
    for a, _, ci in ((a, n, r) for a, n, r in records if isinstance(r, ChunkIndex)):
        c = by_offset.get(ci.chunk_start_offset)
        if c is None:
            problems.add("chunk index", f"ChunkIndex at {a}: no chunk at offset {ci.chunk_start_offset}")
            continue
        if ci.chunk_start_offset in indexed:
            problems.add("chunk index", f"chunk at offset {ci.chunk_start_offset} indexed twice")
        indexed.add(ci.chunk_start_offset)
        ch = c["chunk"]
        idx = c["index_records"] or []
        want = {
            "chunk_length": c["length"],
            "message_start_time": ch.message_start_time,
            "message_end_time": ch.message_end_time,
            "compression": ch.compression,
            "compressed_size": len(ch.data),
            "uncompressed_size": ch.uncompressed_size,
            "message_index_offsets": {mi.channel_id: ma for ma, _, mi in idx},
            "message_index_length": sum(n for _, n, _ in idx),
        }
        for k, v in want.items():
            got = getattr(ci, k)
            if k == "message_index_offsets":
                got = dict(got)
            if got != v:
                problems.add("chunk index", f"ChunkIndex of the chunk at {ci.chunk_start_offset}: {k} {got}, the file says {v}")
        if idx and idx[0][0] != c["offset"] + c["length"]:
            problems.add("chunk index", f"chunk at {c['offset']}: its message indexes do not follow it")
    for c in lin.chunks:
        if c["offset"] not in indexed:
            problems.add("chunk index", f"the chunk at offset {c['offset']} has no ChunkIndex")

    def check_index(kind, index_type, found, fields):
        idxs = [r for _, _, r in records if isinstance(r, index_type)]
        at = {a: (n, r) for a, n, r in found}
        seen = set()
        for ix in idxs:
            got = at.get(ix.offset)
            if got is None:
                problems.add(kind, f"{index_type.__name__} {ix.name!r}: no {kind} record at offset {ix.offset}")
                continue
            seen.add(ix.offset)
            n, r = got
            want = dict(fields(n, r))
            for k, v in want.items():
                if getattr(ix, k) != v:
                    problems.add(kind, f"{index_type.__name__} {ix.name!r}: {k} {getattr(ix, k)}, the record says {v}")
        for a in set(at) - seen:
            problems.add(kind, f"the {kind} record at offset {a} ({at[a][1].name!r}) has no {index_type.__name__}")

    check_index(
        "attachment",
        AttachmentIndex,
        lin.attachments,
        lambda n, r: {
            "length": n,
            "log_time": r.log_time,
            "create_time": r.create_time,
            "data_size": len(r.data),
            "name": r.name,
            "media_type": r.media_type,
        },
    )
    check_index("metadata", MetadataIndex, lin.metadata, lambda n, r: {"length": n, "name": r.name})
    for r in records:
        if not isinstance(r[2], (Schema, Channel, Statistics, ChunkIndex, AttachmentIndex, MetadataIndex)):
            problems.add("summary", f"a {type(r[2]).__name__} record at {r[0]} in the summary")
    return stats[0] if len(stats) == 1 else None


def ranges(values):
    """sorted distinct values as "0-155,157-181" (the ledgers' format)"""
    out, run = [], None
    for v in sorted(set(values)):
        if run and v == run[1] + 1:
            run[1] = v
        else:
            run = [v, v]
            out.append(run)
    return ",".join(str(a) if a == b else f"{a}-{b}" for a, b in out)


def record_opcode(r):
    return Opcode(record_bytes(r)[0])


def library_read(path, lin, problems, expect_cut, report):
    """the library's own readers: every message decoded with its schema,
    attachments and metadata records read back; counts against the linear read"""
    decoders = JsonSchemaDecoders(problems)
    topics, decoded, raw = {}, 0, 0
    previous = None
    with open(path, "rb") as f:
        if expect_cut:
            # the indexed reader needs the footer: say what it does with a cut file
            try:
                make_reader(f, validate_crcs=True).get_summary()
                report["indexed_reader"] = "opened the file"
            except Exception as e:  # noqa: BLE001
                report["indexed_reader"] = f"refused: {type(e).__name__}: {e}"
            f.seek(0)
            reader = NonSeekingReader(f, validate_crcs=True, decoder_factories=[decoders])
            how = "NonSeekingReader (stream, file order)"
            messages = reader.iter_decoded_messages(log_time_order=False)
        else:
            reader = make_reader(f, validate_crcs=True, decoder_factories=[decoders])
            how = f"{type(reader).__name__} (chunk indexes, log-time order)"
            messages = reader.iter_decoded_messages(log_time_order=True)
        stopped = None
        try:
            for schema, channel, message, (value, error) in messages:
                topics[channel.topic] = topics.get(channel.topic, 0) + 1
                if value is RAW:
                    raw += 1
                elif error is not None:
                    problems.add("decode", f"{channel.topic} seq {message.sequence} at {message.log_time} ns: {error}")
                else:
                    decoded += 1
                if not expect_cut and previous is not None and message.log_time < previous:
                    problems.add("order", f"the indexed reader gave {message.log_time} after {previous}")
                previous = message.log_time
        except (EndOfFile, struct.error) as e:
            stopped = f"{type(e).__name__} {e}".strip()
        except Exception as e:  # noqa: BLE001
            problems.add("library read", f"{how} stopped: {type(e).__name__}: {e}")
        if stopped is not None:
            if expect_cut and lin.cut:
                report["stream_read_ends"] = f"at the cut ({stopped})"
            else:
                problems.add("library read", f"{how} stopped: {stopped}")
        report["library_reader"] = how
        report["decoded"] = decoded
        report["raw_lcm_not_decoded"] = raw
        if topics != lin.topic_counts:
            problems.add("library read", f"{how} read {topics}, the linear read {lin.topic_counts}")

        # attachments and metadata records, through the library's reader
        # (a non-seeking reader serves one query per pass: one each)
        atts, metas = [], []
        for what, out in (("attachments", atts), ("metadata", metas)):
            f.seek(0)
            r = NonSeekingReader(f, validate_crcs=True) if expect_cut else make_reader(f, validate_crcs=True)
            try:
                if what == "attachments":
                    out.extend((a.name, a.media_type, a.data) for a in r.iter_attachments())
                else:
                    out.extend((m.name, m.metadata) for m in r.iter_metadata())
            except (EndOfFile, struct.error) as e:
                if not (expect_cut and lin.cut):
                    problems.add("library read", f"{what}: {type(e).__name__}: {e}")
            except Exception as e:  # noqa: BLE001
                problems.add("library read", f"{what}: {type(e).__name__}: {e}")
        if atts != [(r.name, r.media_type, r.data) for _, _, r in lin.attachments]:
            problems.add("attachment", f"the library's reader read {[a[0] for a in atts]}, the file holds {[r.name for _, _, r in lin.attachments]}")
        if metas != [(r.name, r.metadata) for _, _, r in lin.metadata]:
            problems.add("metadata", f"the library's reader read {[m[0] for m in metas]}, the file holds {[r.name for _, _, r in lin.metadata]}")


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    flags = [a for a in argv[1:] if a.startswith("--")]
    if len(args) != 1 or any(f != "--expect-cut" for f in flags):
        print("usage: mcap_py_check.py FILE.mcap [--expect-cut]", file=sys.stderr)
        return 2
    path, expect_cut = args[0], "--expect-cut" in flags
    try:
        with open(path, "rb") as f:
            magic = f.read(8)
    except OSError as e:
        print(f"mcap_py_check: {e}", file=sys.stderr)
        return 2
    problems = Problems()
    report = {"file": path, "bytes": os.path.getsize(path), "reader": f"mcap {version('mcap')} (Python), jsonschema {version('jsonschema')}"}
    if magic != b"\x89MCAP0\r\n":
        problems.add("layout", f"not an MCAP file: magic {magic!r}")
    else:
        lin = Linear(path, problems)
        lin.run()
        lin.end_of_chunk_indexes()
        complete = lin.footer is not None
        report["header"] = lin.header and {"profile": lin.header.profile, "library": lin.header.library}
        if complete:
            with open(path, "rb") as f:
                f.seek(-8, io.SEEK_END)
                if f.read(8) != magic:
                    problems.add("layout", "no magic after the footer")
            report["end"] = "complete: footer, summary, magic"
            if expect_cut:
                problems.add("end", "--expect-cut, but the file is complete (footer and summary)")
            check_summary(lin, problems, path)
        elif lin.broken:
            report["end"] = "unreadable: " + lin.broken
        elif lin.cut or lin.records:
            report["end"] = "cut: " + (lin.cut or "no footer after the last whole record")
            if not expect_cut:
                problems.add("end", f"the file is cut (no footer): {report['end']}")
            if lin.data_end is not None:
                report["end"] += "; the data section ended (DataEnd) before the cut"
            if lin.chunks and not lin.chunks[-1]["index_records"]:
                report["end"] += "; the last chunk's message indexes were cut"
        library_read(path, lin, problems, expect_cut, report)
        sec = lambda ns: round(ns / 1e9, 6)  # noqa: E731
        report.update(
            {
                "messages": lin.messages,
                "topics": dict(sorted(lin.topic_counts.items())),
                "log_times_s": {t: [sec(a), sec(b)] for t, (a, b) in sorted(lin.topic_times.items())},
                # the Message records' sequence fields per topic, and how many repeat one
                "sequences": {t: ranges(v) for t, v in sorted(lin.sequences.items())},
                "repeated_sequences": {t: len(v) - len(set(v)) for t, v in sorted(lin.sequences.items()) if len(v) != len(set(v))},
                "schemas": {s.id: f"{s.name} ({s.encoding})" for s in lin.schemas.values()},
                "channels": len(lin.channels),
                "message_encodings": sorted({c.message_encoding for c in lin.channels.values()}),
                "chunks": len(lin.chunks),
                "compression": {k or "none": sum(1 for c in lin.chunks if c["chunk"].compression == k) for k in sorted({c["chunk"].compression for c in lin.chunks})},
                "attachments": [r.name for _, _, r in lin.attachments],
                "metadata": [r.name for _, _, r in lin.metadata],
                "metadataRecords": {r.name: r.metadata for _, _, r in lin.metadata},
            }
        )
        for c in lin.channels.values():
            s = lin.schemas.get(c.schema_id)
            if c.message_encoding == "lcm" and c.schema_id == 0 and c.topic.startswith("lcm/"):
                continue  # `record --raw`'s LCM bytes
            if c.message_encoding != "json":
                problems.add("channel", f"{c.topic}: message encoding {c.message_encoding!r}, not json")
            if s is None or s.encoding != "jsonschema":
                problems.add("channel", f"{c.topic}: schema {s and s.encoding!r}, not jsonschema")
    report["problem_counts"] = problems.kinds
    report["problems"] = problems.items
    print(json.dumps(report, indent=1))
    out = sys.stderr
    raw = f", {report['raw_lcm_not_decoded']} raw LCM (read, not decoded)" if report.get("raw_lcm_not_decoded") else ""
    print(f"mcap_py_check: {path}: {report.get('end', '?')}; {report.get('messages', 0)} messages, "
          f"{report.get('decoded', 0)} decoded and valid{raw}, {report.get('chunks', 0)} chunks "
          f"({report['reader']})", file=out)
    for t, n in report.get("topics", {}).items():
        a, b = report["log_times_s"][t]
        print(f"  {t}: {n} ({a} .. {b} s)", file=out)
    for p in problems.items:
        print(f"FAIL: {p}", file=out)
    return 1 if problems.items else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
