//! Storage format: exact round trip, and hostile bytes never panic. Mutated
//! values get a recomputed content hash so that structural validation (not
//! the hash) has to catch them.
use tinmerge_core::tin::build::build;
use tinmerge_core::tin::layout::{
    self, body_offset, decode, encode, encode_v3, read_header, reseal,
};
use tinmerge_core::tin::{NONE, Tin, TinError, locate};

fn sample_tin() -> Vec<u8> {
    encode(&sample())
}

/// The sample in format 3, whose arrays sit at fixed places (the crafted
/// cases below write into them).
fn sample_v3() -> Vec<u8> {
    encode_v3(&sample())
}

fn sample() -> Tin {
    // a seeded pseudo-random terrain on a 40 x 40 grid
    let mut s: u64 = 0x5eed;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s % 1000) as f64 / 100.0
    };
    let mut pts = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            let (x, y) = (i as f64 * 10.0, j as f64 * 10.0);
            pts.push([x, y, (x / 30.0).sin() * 20.0 + rnd()]);
        }
    }
    let tin = build(pts, &[8.0, 4.0, 1.0], 32616, &mut || Ok(())).unwrap();
    tin.sanity_check().unwrap();
    tin
}

fn rehash(b: &mut [u8]) {
    reseal(b);
}

#[test]
fn roundtrip_is_exact() {
    let b = sample_tin();
    let t = decode(&b).unwrap();
    assert_eq!(encode(&t), b);
}

/// Format 4 codes its arrays, so bad values are crafted as tins and then
/// encoded: the decoder's checks, not the encoder's, must reject them.
#[test]
fn crafted_tins_in_format_4_are_rejected() {
    let t = sample();
    type Craft = Box<dyn Fn(&mut Tin)>;
    let cases: Vec<(&str, Craft)> = vec![
        (
            "vertex index out of range",
            Box::new(|t| t.levels[0].tris[0][1] = t.verts.len() as u32),
        ),
        (
            "vertex index NONE",
            Box::new(|t| t.levels[1].tris[3][0] = NONE),
        ),
        (
            "non-finite coordinate",
            Box::new(|t| t.verts[5][2] = f64::NAN),
        ),
        (
            "swapped corners",
            Box::new(|t| t.levels[2].tris[7].swap(0, 1)),
        ),
        (
            "neighbour out of range",
            Box::new(|t| t.levels[1].nbrs[2][0] = 1 << 30),
        ),
        (
            "neighbour not symmetric",
            Box::new(|t| {
                let n = t.levels[2].nbrs[0];
                let j = (0..3).find(|&j| n[j] != NONE).unwrap();
                t.levels[2].nbrs[0][j] = (n[j] + 1) % t.levels[2].tris.len() as u32;
            }),
        ),
        (
            "parent out of range",
            Box::new(|t| t.levels[1].parent[4] = 1 << 20),
        ),
        (
            "parents not sorted",
            Box::new(|t| t.levels[2].parent.swap(0, 9)),
        ),
        (
            "grid cell out of range",
            Box::new(|t| t.levels[0].grid.cells[0] = 1 << 25),
        ),
    ];
    for (name, f) in cases {
        let mut m = t.clone();
        f(&mut m);
        match decode(&encode(&m)) {
            Err(TinError::Corrupt(msg)) => eprintln!("{name}: {msg}"),
            other => panic!("{name}: expected a Corrupt error, got {other:?}"),
        }
    }
}

#[test]
fn crafted_values_with_valid_hash_are_rejected() {
    let b = sample_v3();
    let h = read_header(&b).unwrap();
    let body = body_offset(&h, 0);
    let nv = u32::from_le_bytes(b[20..24].try_into().unwrap()) as usize;
    let tris = body_offset(&h, nv * 24); // first triangle of level 0
    type Damage<'a> = Box<dyn Fn(&mut Vec<u8>) + 'a>;
    let cases: Vec<(&str, Damage)> = vec![
        (
            "vertex index out of range",
            Box::new(move |b| b[tris..tris + 4].copy_from_slice(&u32::MAX.to_le_bytes())),
        ),
        (
            "non-finite coordinate",
            Box::new(|b| b[body..body + 8].copy_from_slice(&f64::NAN.to_le_bytes())),
        ),
        (
            "huge triangle count",
            Box::new(|b| b[88 + 16..88 + 20].copy_from_slice(&0x7fff_ffffu32.to_le_bytes())),
        ),
        (
            "zero levels",
            Box::new(|b| b[16..20].copy_from_slice(&0u32.to_le_bytes())),
        ),
        (
            "tolerances not decreasing",
            Box::new(|b| b[88..96].copy_from_slice(&0.5f64.to_le_bytes())),
        ),
        (
            "swapped triangle corners",
            Box::new(move |b| {
                let (x, y) = (tris, tris + 4);
                let a: [u8; 4] = b[x..x + 4].try_into().unwrap();
                let c: [u8; 4] = b[y..y + 4].try_into().unwrap();
                b[x..x + 4].copy_from_slice(&c);
                b[y..y + 4].copy_from_slice(&a);
            }),
        ),
        (
            "bbox that does not match",
            Box::new(|b| b[40..48].copy_from_slice(&(-1e9f64).to_le_bytes())),
        ),
    ];
    for (name, f) in cases {
        let mut m = b.clone();
        f(&mut m);
        rehash(&mut m);
        match decode(&m) {
            Err(TinError::Corrupt(msg)) => eprintln!("{name}: {msg}"),
            other => panic!("{name}: expected a Corrupt error, got {other:?}"),
        }
    }
}

#[test]
fn random_mutations_never_panic() {
    for b in [sample_tin(), sample_v3()] {
        let mut s: u64 = 42;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let (mut ok, mut err) = (0, 0);
        for _ in 0..3000 {
            let mut m = b.clone();
            for _ in 0..(1 + next() % 4) {
                let i = (next() as usize) % m.len();
                m[i] ^= 1 << (next() % 8);
            }
            if next() % 8 == 0 {
                let cut = (next() as usize) % m.len();
                m.truncate(cut);
            }
            if m.len() >= 40 && next() % 2 == 0 {
                rehash(&mut m);
            }
            match decode(&m) {
                Ok(t) => {
                    ok += 1;
                    // a value that passes validation is safe to query
                    for l in 0..t.levels.len() {
                        let _ = locate::locate(&t, l, t.bbox.min_x + 55.0, t.bbox.min_y + 77.0);
                    }
                }
                Err(_) => err += 1,
            }
        }
        eprintln!("{ok} mutated values still valid, {err} rejected");
        assert!(err > 0);
    }
}

#[test]
fn damaged_groups_are_errors_naming_them() {
    let b = sample_tin();
    let h = read_header(&b).unwrap();
    let ranges = layout::group_ranges(&b, &layout::plan(&h)).unwrap();
    assert!(ranges.len() >= 12, "the sample has groups for every array");
    for (k, r) in ranges.iter().enumerate() {
        // a flipped bit in the payload, then in the checksum
        for at in [r.start, r.end - 1] {
            let mut m = b.clone();
            m[at] ^= 0x10;
            let c = layout::content_hash(&m);
            m[32..40].copy_from_slice(&c.to_le_bytes());
            match decode(&m) {
                Err(TinError::Corrupt(msg)) => {
                    assert!(msg.contains(&format!("group {k}")), "{msg}")
                }
                other => panic!("group {k}: expected Corrupt, got {other:?}"),
            }
        }
    }
    // a damaged directory entry: the group it names no longer checks
    let mut m = b.clone();
    m[layout::HEADER_LEN_V4 + 8] ^= 1;
    let c = layout::content_hash(&m);
    m[32..40].copy_from_slice(&c.to_le_bytes());
    assert!(matches!(decode(&m), Err(TinError::Corrupt(_))));
    // a flipped bit in the header: the header hash
    let mut m = b.clone();
    m[870] ^= 1; // the lattice / vertex coding fields
    let c = layout::content_hash(&m);
    m[32..40].copy_from_slice(&c.to_le_bytes());
    match read_header(&m) {
        Err(TinError::Corrupt(msg)) => assert!(msg.contains("header hash"), "{msg}"),
        other => panic!("expected a header hash error, got {other:?}"),
    }
}

#[test]
fn damaged_blocks_and_headers_are_errors_naming_them() {
    let b = sample_v3();
    let h = read_header(&b).unwrap();
    // a flipped bit anywhere in a block's payload or checksum: that block
    let blocks = (b.len() - tinmerge_core::tin::layout::HEADER_LEN_V3)
        .div_ceil(tinmerge_core::tin::layout::BLOCK_LEN);
    assert!(blocks >= 3, "the sample spans several blocks");
    for k in 0..blocks {
        let at = body_offset(&h, k * tinmerge_core::tin::layout::BLOCK_PAYLOAD) + 17;
        let mut m = b.clone();
        m[at.min(b.len() - 1)] ^= 0x10;
        // with the whole value's hash recomputed, the block's own checksum
        // must catch it (a sliced read sees only that)
        let c = tinmerge_core::tin::layout::content_hash(&m);
        m[32..40].copy_from_slice(&c.to_le_bytes());
        match decode(&m) {
            Err(TinError::Corrupt(msg)) => {
                assert!(msg.contains(&format!("block {k}")), "{msg}")
            }
            other => panic!("block {k}: expected Corrupt, got {other:?}"),
        }
    }
    // a flipped bit in the header: the header hash, even with the whole
    // value's hash recomputed
    let mut m = b.clone();
    m[45] ^= 1;
    let c = tinmerge_core::tin::layout::content_hash(&m);
    m[32..40].copy_from_slice(&c.to_le_bytes());
    match read_header(&m) {
        Err(TinError::Corrupt(msg)) => assert!(msg.contains("header hash"), "{msg}"),
        other => panic!("expected a header hash error, got {other:?}"),
    }
}
