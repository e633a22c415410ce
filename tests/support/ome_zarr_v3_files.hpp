// Small OME-Zarr 0.5 (Zarr v3) images written by a fixture script that follows the Zarr v3
// specification literally (Debian's zarr 2.13 has no final v3): zarr.json documents, chunk keys,
// the codec chain (transpose, bytes, gzip, zstd, blosc, crc32c) and sharding_indexed shards,
// compressed by numcodecs, with a pure-Python CRC-32C. Run after kZarrPrelude (its ref()).
#pragma once
#include <string>

#include "ome_zarr_files.hpp"

namespace imx::test {

// array3(path, data, chunks, codecs, ...) writes one v3 array; image3(name, levels, ...) an
// OME-NGFF 0.5 group of such arrays (levels "0", "1", ...), with "omero" when given. A codec is
// (name, configuration) as zarr.json spells it; keep(index) says which chunks are written (the
// others are missing and read as the fill value); a shard leaves out inner chunks of the fill
// value only, as zarr does. array3 returns what the array holds, for ref().
inline const char* kZarr3Prelude = R"PY(
import gzip as gzip_module, itertools, struct

def _crc32c_table():
    table = []
    for n in range(256):
        c = n
        for _ in range(8):
            c = (0x82F63B78 ^ (c >> 1)) if c & 1 else c >> 1
        table.append(c)
    return table
_CRC = _crc32c_table()

def crc32c(data):
    c = 0xFFFFFFFF
    for b in data:
        c = _CRC[(c ^ b) & 0xFF] ^ (c >> 8)
    return c ^ 0xFFFFFFFF
assert crc32c(b'123456789') == 0xE3069283

def v3_type(dtype):
    d = np.dtype(dtype)
    return {'i': 'int', 'u': 'uint', 'f': 'float'}[d.kind] + str(8 * d.itemsize)

def codec(name, **configuration):
    return {'name': name, 'configuration': configuration} if configuration else {'name': name}

SHUFFLES = {'noshuffle': Blosc.NOSHUFFLE, 'shuffle': Blosc.SHUFFLE, 'bitshuffle': Blosc.BITSHUFFLE}

def encode(a, codecs, fill):
    """One chunk (numpy, its full chunk shape) through the chain, in order."""
    b = a
    for c in codecs:
        name, cfg = c['name'], c.get('configuration', {})
        if name == 'transpose':
            b = np.ascontiguousarray(np.transpose(b, cfg['order']))
        elif name == 'bytes':
            order = '>' if cfg.get('endian') == 'big' else '<'
            b = b.astype(b.dtype.newbyteorder(order)).tobytes(order='C')
        elif name == 'sharding_indexed':
            b = encode_shard(b, cfg, fill)
        elif name == 'gzip':
            b = gzip_module.compress(b, compresslevel=cfg.get('level', 5))
        elif name == 'zstd':
            b = bytes(Zstd(level=cfg.get('level', 0)).encode(b))
        elif name == 'blosc':
            typesize = cfg.get('typesize', 1)
            blosc = Blosc(cname=cfg['cname'], clevel=cfg['clevel'], shuffle=SHUFFLES[cfg['shuffle']])
            b = bytes(blosc.encode(np.frombuffer(b, dtype='u%d' % typesize)))
        elif name == 'crc32c':
            b = b + struct.pack('<I', crc32c(b))
        else:
            b = c['raw'](b)  # a test's own codec
    return b

def encode_shard(a, cfg, fill):
    inner = cfg['chunk_shape']
    grid = [s // c for s, c in zip(a.shape, inner)]
    parts, index = [], np.full(grid + [2], 2**64 - 1, dtype='<u8')
    index_codecs = cfg['index_codecs']
    index_size = len(encode(index, index_codecs, 0))
    at_start = cfg.get('index_location', 'end') == 'start'
    offset = index_size if at_start else 0
    for pos in itertools.product(*[range(g) for g in grid]):
        sl = tuple(slice(p * c, (p + 1) * c) for p, c in zip(pos, inner))
        if np.all(a[sl] == fill):
            continue  # as zarr writes it: an inner chunk of the fill value is not stored
        data = encode(np.ascontiguousarray(a[sl]), cfg['codecs'], fill)
        index[pos] = (offset, len(data))
        parts.append(data)
        offset += len(data)
    idx = encode(index, index_codecs, 0)
    return idx + b''.join(parts) if at_start else b''.join(parts) + idx

def array3(path, data, chunks, codecs, fill_value=0, key='default', separator=None,
           dimension_names=None, keep=None, extra=None):
    os.makedirs(path, exist_ok=True)
    if isinstance(fill_value, float) and np.isnan(fill_value):
        fill_json, fill = 'NaN', np.nan
    elif isinstance(fill_value, str):
        fill_json, fill = fill_value, np.frombuffer(bytes.fromhex(fill_value[2:])[::-1],
                                                 data.dtype.newbyteorder('<'))[0]
    else:
        fill_json, fill = fill_value, fill_value
    enc = {'name': key}
    if separator:
        enc['configuration'] = {'separator': separator}
    sep = separator or ('/' if key == 'default' else '.')
    meta = {'zarr_format': 3, 'node_type': 'array', 'shape': list(data.shape),
            'data_type': v3_type(data.dtype),
            'chunk_grid': {'name': 'regular', 'configuration': {'chunk_shape': list(chunks)}},
            'chunk_key_encoding': enc, 'fill_value': fill_json,
            'codecs': [{k: v for k, v in c.items() if k != 'raw'} for c in codecs],
            'attributes': {}}
    if dimension_names:
        meta['dimension_names'] = list(dimension_names)
    meta.update(extra or {})
    json.dump(meta, open(os.path.join(path, 'zarr.json'), 'w'), indent=1)
    grid = [-(-s // c) for s, c in zip(data.shape, chunks)]
    full = np.full([g * c for g, c in zip(grid, chunks)], fill, dtype=data.dtype)
    full[tuple(slice(0, s) for s in data.shape)] = data
    for pos in itertools.product(*[range(g) for g in grid]):
        if keep is not None and not keep(pos):
            continue
        sl = tuple(slice(p * c, (p + 1) * c) for p, c in zip(pos, chunks))
        parts = ([] if key == 'v2' else ['c']) + [str(p) for p in pos]
        file = os.path.join(path, *sep.join(parts).split('/'))
        os.makedirs(os.path.dirname(file), exist_ok=True)
        with open(file, 'wb') as f:
            f.write(encode(np.ascontiguousarray(full[sl]), codecs, fill))
    # The reference: what the array holds, missing chunks as the fill value.
    expect = full.copy()
    if keep is not None:
        for pos in itertools.product(*[range(g) for g in grid]):
            if not keep(pos):
                expect[tuple(slice(p * c, (p + 1) * c) for p, c in zip(pos, chunks))] = fill
    return expect[tuple(slice(0, s) for s in data.shape)]

def image3(name, levels, axes='zyx', chunks=None, codecs=None, scales=None, omero=None, **kw):
    os.makedirs(name, exist_ok=True)
    kinds = {'t': 'time', 'c': 'channel', 'z': 'space', 'y': 'space', 'x': 'space'}
    datasets, out = [], []
    for i, data in enumerate(levels):
        ch = chunks[i] if chunks else data.shape
        out.append(array3(os.path.join(name, str(i)), data, ch,
                          codecs or [codec('bytes', endian='little')],
                          dimension_names=list(axes), **kw))
        s = scales[i] if scales else [1.0] * data.ndim
        datasets.append({'path': str(i), 'coordinateTransformations': [{'type': 'scale', 'scale': s}]})
    ome = {'version': '0.5', 'multiscales': [{'name': name, 'datasets': datasets,
           'axes': [{'name': n, 'type': kinds[n]} for n in axes]}]}
    if omero:
        ome['omero'] = omero
    json.dump({'zarr_format': 3, 'node_type': 'group', 'attributes': {'ome': ome}},
              open(os.path.join(name, 'zarr.json'), 'w'), indent=1)
    return out
)PY";

// Runs both preludes and `snippet` in `dir` (run_zarr_python's contract).
inline bool run_zarr3_python(const TempDir& dir, const std::string& snippet) {
  return run_zarr_python(dir, std::string(kZarr3Prelude) + snippet);
}

}  // namespace imx::test
