//! What the area sweep ([`super::sweep()`]) works in and keeps per thread:
//! its vectors ([`Scratch`]) and the flag bytes of a level's triangles
//! ([`Flags`]). A zonal join sweeps a boundary tile per row; allocating
//! these afresh was a tenth of a row's time.

use crate::merge::area::clip::{Chain, ChainPoints};

/// A ring segment met in a triangle: (triangle, ring, segment).
pub(super) type Pair = (u32, u32, u32);

/// The vectors a sweep works in, kept per thread for the next sweep: a
/// zonal join sweeps a boundary tile per row, and allocating them afresh
/// was a tenth of its time. A sweep takes them ([`Scratch::take`]) and
/// gives them back when it is done; a [`super::Sweep`] gives back its own when
/// dropped. (A sweep that fails leaves them to be dropped.)
#[derive(Default)]
pub(super) struct Scratch {
    pub(super) pairs: Vec<Pair>,
    pub(super) pending: Vec<Pair>,
    pub(super) next: Vec<Pair>,
    pub(super) pieces: Vec<(u32, u32, ChainPoints)>,
    pub(super) tagged: Vec<(u32, u32, Chain)>,
    pub(super) chains: Vec<Chain>,
    pub(super) seeds: Vec<u32>,
    pub(super) stack: Vec<(u32, bool)>,
    /// vectors of triangle ids (emptied when taken: [`Scratch::list`])
    pub(super) lists: Vec<Vec<u32>>,
}

/// Vectors of triangle ids kept in a [`Scratch`].
const SPARE_LISTS: usize = 64;
/// Capacity past which a vector is not kept (a sweep of a whole large
/// terrain's level gives its memory back).
const KEEP_CAPACITY: usize = 1 << 16;

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

impl Scratch {
    /// The thread's vectors (empty ones when another sweep of the thread
    /// holds them, or while its storage is torn down).
    pub(super) fn take() -> Scratch {
        SCRATCH
            .try_with(|c| {
                c.try_borrow_mut()
                    .map(|mut s| std::mem::take(&mut *s))
                    .unwrap_or_default()
            })
            .unwrap_or_default()
    }

    /// Back to the thread, emptied, but for vectors grown past
    /// [`KEEP_CAPACITY`].
    pub(super) fn give_back(mut self) {
        fn keep<T>(v: &mut Vec<T>) {
            v.clear();
            if v.capacity() > KEEP_CAPACITY {
                *v = Vec::new();
            }
        }
        keep(&mut self.pairs);
        keep(&mut self.pending);
        keep(&mut self.next);
        keep(&mut self.pieces);
        keep(&mut self.tagged);
        keep(&mut self.chains);
        keep(&mut self.seeds);
        keep(&mut self.stack);
        self.lists.retain(|v| v.capacity() <= KEEP_CAPACITY);
        self.lists.truncate(SPARE_LISTS);
        let _ = SCRATCH.try_with(|c| {
            if let Ok(mut s) = c.try_borrow_mut() {
                *s = self;
            }
        });
    }

    /// An empty vector of triangle ids.
    pub(super) fn list(&mut self) -> Vec<u32> {
        let mut v = self.lists.pop().unwrap_or_default();
        v.clear();
        v
    }

    /// A dropped [`super::Sweep`]'s vectors (its triangle lists and its
    /// chains), kept for the next sweep of the thread when there is room.
    pub(super) fn keep(lists: impl Iterator<Item = Vec<u32>>, mut chains: Vec<Chain>) {
        let _ = SCRATCH.try_with(|c| {
            let Ok(mut s) = c.try_borrow_mut() else {
                return;
            };
            for v in lists {
                if s.lists.len() < SPARE_LISTS && v.capacity() > 0 && v.capacity() <= KEEP_CAPACITY
                {
                    s.lists.push(v);
                }
            }
            if chains.capacity() > s.chains.capacity() && chains.capacity() <= KEEP_CAPACITY {
                chains.clear();
                s.chains = chains;
            }
        });
    }
}

/// Flag bytes of the triangles of one level (or of the vertices), zero
/// until set. A level of up to [`FLAT_FLAGS`] triangles (a tile's) has
/// them in one vector; a larger one keeps them in pages allocated when
/// first written: a sweep of a small polygon over a large terrain costs
/// what it touches, not a byte per triangle of every level it sweeps.
/// Vectors and pages are kept for the next sweep of the thread when
/// dropped (a tile of a county's boundary sweeps six levels, and these
/// sizes are past the allocator's fast path).
#[derive(Default)]
pub(super) struct Flags {
    n: usize,
    /// all the flags, when `n <= FLAT_FLAGS`
    flat: Vec<u8>,
    pages: Vec<Option<Box<[u8; FLAG_PAGE]>>>,
}

const FLAG_PAGE: usize = 4096;
/// Levels up to this many triangles have their flags in one vector.
const FLAT_FLAGS: usize = 4 * FLAG_PAGE;
/// Zeroed pages kept per thread.
const SPARE_PAGES: usize = 64;

/// Vectors kept per thread.
const SPARE_FLAT: usize = 16;

thread_local! {
    static SPARE: std::cell::RefCell<Vec<Box<[u8; FLAG_PAGE]>>> = const { std::cell::RefCell::new(Vec::new()) };
    static SPARE_VECS: std::cell::RefCell<Vec<Vec<u8>>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl Flags {
    pub(super) fn new(n: usize) -> Flags {
        if n <= FLAT_FLAGS {
            let mut flat = SPARE_VECS
                .try_with(|s| s.borrow_mut().pop())
                .ok()
                .flatten()
                .unwrap_or_default();
            flat.resize(n, 0);
            return Flags {
                n,
                flat,
                pages: Vec::new(),
            };
        }
        Flags {
            n,
            flat: Vec::new(),
            pages: (0..n.div_ceil(FLAG_PAGE)).map(|_| None).collect(),
        }
    }

    /// The flags of triangle `t` (None out of range).
    pub(super) fn get(&self, t: usize) -> Option<u8> {
        (t < self.n).then(|| self[t])
    }

    pub(super) fn get_mut(&mut self, t: usize) -> Option<&mut u8> {
        if t >= self.n {
            return None;
        }
        if self.pages.is_empty() {
            return self.flat.get_mut(t);
        }
        let page = self.pages[t / FLAG_PAGE].get_or_insert_with(|| {
            SPARE
                .try_with(|s| s.borrow_mut().pop())
                .ok()
                .flatten()
                .unwrap_or_else(|| Box::new([0; FLAG_PAGE]))
        });
        Some(&mut page[t % FLAG_PAGE])
    }
}

impl Drop for Flags {
    fn drop(&mut self) {
        if self.pages.is_empty() {
            let mut flat = std::mem::take(&mut self.flat);
            if flat.capacity() > 0 {
                flat.clear();
                let _ = SPARE_VECS.try_with(|s| {
                    let mut s = s.borrow_mut();
                    if s.len() < SPARE_FLAT {
                        s.push(flat);
                    }
                });
            }
            return;
        }
        // (not at all while the thread's storage is being torn down)
        let _ = SPARE.try_with(|s| {
            let mut s = s.borrow_mut();
            for mut p in self.pages.drain(..).flatten() {
                if s.len() >= SPARE_PAGES {
                    break;
                }
                p.fill(0);
                s.push(p);
            }
        });
    }
}

impl std::ops::Index<usize> for Flags {
    type Output = u8;
    fn index(&self, t: usize) -> &u8 {
        assert!(t < self.n, "flag {t} of {}", self.n);
        if self.pages.is_empty() {
            return &self.flat[t];
        }
        self.pages[t / FLAG_PAGE]
            .as_ref()
            .map_or(&0, |p| &p[t % FLAG_PAGE])
    }
}

impl std::ops::IndexMut<usize> for Flags {
    fn index_mut(&mut self, t: usize) -> &mut u8 {
        let n = self.n;
        self.get_mut(t).unwrap_or_else(|| panic!("flag {t} of {n}"))
    }
}
