# Hostile DICOM inputs for `scripts/hostile-sweep --dicom` (issue 48, item 9): files and folders
# made from ../shared/data/dicom by cutting, relabelling and lying, and the file-system cases
# (unreadable files and folders, link loops, FIFOs, empty folders). write_cases(folder, data)
# returns (path given to intermix, what it is, the name the message must hold, as_other_user,
# words of the reason the message must give, or None): as_other_user cases need a user without
# root's permission override (the sweep drops to nobody).
import gzip
import os
import shutil
import struct

# (group, element) of the tags edited here.
PIXEL_DATA = (0x7FE0, 0x0010)
TRANSFER_SYNTAX = (0x0002, 0x0010)
ROWS, COLUMNS = (0x0028, 0x0010), (0x0028, 0x0011)
LONG_VRS = {b"OB", b"OD", b"OF", b"OL", b"OV", b"OW", b"SQ", b"UC", b"UN", b"UR", b"UT", b"SV",
            b"UV"}


def elements(data):
    """(tag, vr, header offset, value offset, length) of each top-level element of an explicit
    VR little-endian file with a preamble; stops at the pixel data or a sequence of undefined
    length (whose items this does not walk)."""
    at = 132
    while at + 8 <= len(data):
        group, element = struct.unpack_from("<HH", data, at)
        vr = data[at + 4:at + 6]
        if vr in LONG_VRS:
            (length,) = struct.unpack_from("<I", data, at + 8)
            value = at + 12
        else:
            (length,) = struct.unpack_from("<H", data, at + 6)
            value = at + 8
        yield (group, element), vr, at, value, length
        if (group, element) == PIXEL_DATA or length == 0xFFFFFFFF:
            return
        at = value + length


def find(data, tag):
    for t, vr, at, value, length in elements(data):
        if t == tag:
            return vr, at, value, length
    return None


def without(data, tag):
    """The file with element `tag` removed (the group length of the meta group, when it is
    there, left as it was: DICOM readers take the elements as they come)."""
    _, at, value, length = find(data, tag)
    return data[:at] + data[value + length:]


def with_text(data, tag, text):
    """Element `tag` (a short-VR text element) given the value `text`, padded to even length;
    the meta group's length is corrected when the element is in it."""
    vr, at, value, length = find(data, tag)
    raw = text.encode() + (b"\0" if len(text) % 2 else b"")
    out = data[:value - 2] + struct.pack("<H", len(raw)) + raw + data[value + length:]
    if tag[0] == 0x0002:
        meta = find(out, (0x0002, 0x0000))
        if meta:
            _, _, mvalue, _ = meta
            (old,) = struct.unpack_from("<I", out, mvalue)
            out = out[:mvalue] + struct.pack("<I", old + len(raw) - length) + out[mvalue + 4:]
    return out


def with_length(data, tag, length):
    """Element `tag`'s length field set to `length` (a lie: the value is left as it was)."""
    vr, at, value, _ = find(data, tag)
    if vr in LONG_VRS:
        return data[:at + 8] + struct.pack("<I", length) + data[at + 12:]
    return data[:at + 6] + struct.pack("<H", length) + data[at + 8:]


def write_cases(folder, data):
    """Writes the cases under `folder` from the shared data folder `data`; returns their list."""
    ts = os.path.join(data, "dicom", "ts")
    series = os.path.join(data, "dicom", "ct-philips")
    explicit = open(os.path.join(ts, "1.dcm"), "rb").read()  # explicit VR little endian, native
    jpeg = open(os.path.join(ts, "5.dcm"), "rb").read()  # JPEG lossless, encapsulated
    cases = []

    def put(name, content, what, reason=None, other_user=False):
        path = os.path.join(folder, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(content)
        cases.append((path, what, os.path.basename(path), other_user, reason))
        return path

    def copy_series(name):
        path = os.path.join(folder, name)
        shutil.copytree(series, path)
        for f in os.listdir(path):
            os.chmod(os.path.join(path, f), 0o644)
        os.chmod(path, 0o755)
        return path

    # Files cut short at each part: the preamble, the meta group, the data set, the pixels.
    _, _, pixels, _ = find(explicit, PIXEL_DATA)
    for label, at in [("preamble", 100), ("meta", 140), ("dataset", pixels // 2),
                      ("pixel-header", pixels - 6), ("pixels", pixels + 1000)]:
        put(f"cut-{label}.dcm", explicit[:at], f"cut inside its {label}",
            "file meta" if label == "meta" else None)
    put("empty.dcm", b"", "an empty .dcm file", "not a DICOM file")
    put("text.dcm", b"this is not a DICOM file\n" * 20, "text named .dcm", "not a DICOM file")
    put("no-pixels.dcm", without(explicit, PIXEL_DATA), "a DICM file without pixel data",
        "no pixel data")
    put("no-rows.dcm", without(explicit, ROWS), "no Rows (0028,0010)", "no Rows (0028,0010)")
    put("no-columns.dcm", without(explicit, COLUMNS), "no Columns (0028,0011)",
        "no Columns (0028,0011)")
    put("ts-unknown.dcm", with_text(explicit, TRANSFER_SYNTAX, "1.2.3.4.5.6"),
        "an unknown transfer syntax", "transfer syntax '1.2.3.4.5.6'")
    put("ts-jpeg-on-native.dcm", with_text(explicit, TRANSFER_SYNTAX, "1.2.840.10008.1.2.4.50"),
        "JPEG baseline named over native pixels",
        "says the pixel data is compressed")
    put("ts-native-on-jpeg.dcm", with_text(jpeg, TRANSFER_SYNTAX, "1.2.840.10008.1.2.1"),
        "explicit little endian named over JPEG fragments",
        "says the pixel data is not compressed")
    put("ts-missing.dcm", without(explicit, TRANSFER_SYNTAX), "no TransferSyntaxUID",
        "no TransferSyntaxUID")
    put("ts-deflated.dcm", with_text(explicit, TRANSFER_SYNTAX, "1.2.840.10008.1.2.1.99"),
        "the deflated transfer syntax over a plain data set",
        "deflated")
    put("ts-big-endian.dcm", with_text(explicit, TRANSFER_SYNTAX, "1.2.840.10008.1.2.2"),
        "big endian named over a little-endian data set")
    put("cut.dcm.gz", gzip.compress(explicit[:pixels // 2]), "a .dcm.gz whose content is cut")
    put("truncated.dcm.gz", gzip.compress(explicit)[:20000], "a .dcm.gz cut short", "gzip")
    _, _, _, pixel_length = find(explicit, PIXEL_DATA)
    put("pixel-length-long.dcm", with_length(explicit, PIXEL_DATA, pixel_length * 4),
        "a PixelData length past the end of the file")
    put("pixel-length-short.dcm", with_length(explicit, PIXEL_DATA, pixel_length // 2),
        "a PixelData length of half the pixels")
    put("pixel-length-odd.dcm", with_length(explicit, PIXEL_DATA, pixel_length - 1),
        "a PixelData length one byte short (odd)")
    # Folders.
    empty = os.path.join(folder, "empty-folder")
    os.makedirs(empty)
    cases.append((empty, "an empty folder", "empty-folder", False, "no DICOM image files"))
    mixed = copy_series("mixed-series")
    shutil.copy(os.path.join(ts, "1.dcm"), os.path.join(mixed, "other.dcm"))
    shutil.copy(os.path.join(ts, "5.dcm"), os.path.join(mixed, "other-jpeg.dcm"))
    cases.append((mixed, "a folder of three series (read: the largest)", "mixed-series", False,
                  None))
    one_cut = copy_series("series-one-cut")
    victim = sorted(f for f in os.listdir(one_cut) if f != "DIRFILE")[3]
    with open(os.path.join(one_cut, victim), "r+b") as f:
        f.truncate(os.path.getsize(os.path.join(one_cut, victim)) // 2)
    cases.append((one_cut, "a series with one file cut in half", victim, False, None))
    loop = os.path.join(folder, "loop-a.dcm")
    os.symlink("loop-b.dcm", loop)
    os.symlink("loop-a.dcm", os.path.join(folder, "loop-b.dcm"))
    cases.append((loop, "a symbolic link loop", "loop-a.dcm", False, "link loop"))
    with_loop = copy_series("series-with-loop")
    os.symlink("self.dcm", os.path.join(with_loop, "self.dcm"))
    cases.append((with_loop, "a series beside a link loop (read: the loop is passed over)",
                  "series-with-loop", False, None))
    dangling = os.path.join(folder, "dangling.dcm")
    os.symlink("no-such-file.dcm", dangling)
    cases.append((dangling, "a link to a file that is not there", "dangling.dcm", False,
                  "symbolic link to"))
    dicomdir = os.path.join(folder, "dicomdir-only")
    os.makedirs(dicomdir)
    shutil.copy(os.path.join(series, "DIRFILE"), os.path.join(dicomdir, "DIRFILE"))
    cases.append((dicomdir, "a folder holding only its DICOMDIR", "dicomdir-only", False,
                  "no DICOM image files"))
    fifo = os.path.join(folder, "fifo.dcm")
    os.mkfifo(fifo)
    cases.append((fifo, "a FIFO named .dcm", "fifo.dcm", False, "FIFO"))
    dir_named = os.path.join(folder, "folder.dcm")
    os.makedirs(dir_named)
    cases.append((dir_named, "an empty folder named .dcm", "folder.dcm", False, "a folder"))
    # Permissions: only a user without root's override sees these as unreadable.
    locked = put("locked.dcm", explicit, "a file its reader may not read", "Permission denied",
                 other_user=True)
    os.chmod(locked, 0)
    locked_one = copy_series("series-one-locked")
    os.chmod(os.path.join(locked_one, victim), 0)
    cases.append((locked_one, "a series with one file it may not read", victim, True,
                  "Permission denied"))
    locked_dir = copy_series("locked-folder")
    os.chmod(locked_dir, 0)
    cases.append((locked_dir, "a folder it may not list", "locked-folder", True,
                  "Permission denied"))
    locked_sub = os.path.join(folder, "locked-subfolder")
    shutil.copytree(series, os.path.join(locked_sub, "sub"))
    for f in os.listdir(os.path.join(locked_sub, "sub")):
        os.chmod(os.path.join(locked_sub, "sub", f), 0o644)
    os.chmod(os.path.join(locked_sub, "sub"), 0)
    os.chmod(locked_sub, 0o755)
    cases.append((locked_sub, "a folder whose only subfolder it may not list", "sub", True,
                  "Permission denied"))
    os.chmod(folder, 0o755)
    return cases
