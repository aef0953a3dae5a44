//! The driver's queue: triangles by their worst error, largest first,
//! each triangle in it at most once and its key changed in place (an
//! indexed binary max-heap, as delatin keeps). A triangle's entry is
//! `(error's bits, triangle)`: errors are never negative, so their bits
//! order as they do, and ties go to the larger triangle number, so the
//! order of fixes (and so the build) depends on nothing but the keys.
//!
//! Written by hand: the crates that offer a keyed heap (`priority-queue`,
//! `keyed_priority_queue`) find an entry through a hash map, where here
//! the triangle number is the index.

const ABSENT: u32 = u32::MAX;

#[derive(Default)]
pub(super) struct Queue {
    /// the heap: `(error's bits, triangle)`, largest at 0
    heap: Vec<(u64, u32)>,
    /// where triangle `t` is in `heap`, or [`ABSENT`]
    pos: Vec<u32>,
}

impl Queue {
    /// Queue triangle `t` with `key`, or take it out (`None`).
    pub(super) fn set(&mut self, t: u32, key: Option<u64>) {
        let ti = t as usize;
        if self.pos.len() <= ti {
            self.pos.resize(ti + 1, ABSENT);
        }
        let at = self.pos[ti];
        match (key, at) {
            (None, ABSENT) => {}
            (None, i) => self.remove(i as usize),
            (Some(k), ABSENT) => {
                self.heap.push((k, t));
                let i = self.heap.len() - 1;
                self.pos[ti] = i as u32;
                self.up(i);
            }
            (Some(k), i) => {
                let i = i as usize;
                let old = self.heap[i].0;
                self.heap[i].0 = k;
                if k > old {
                    self.up(i);
                } else {
                    self.down(i);
                }
            }
        }
    }

    /// The largest entry, left in the queue.
    pub(super) fn peek(&self) -> Option<(u64, u32)> {
        self.heap.first().copied()
    }

    /// Take the largest entry out.
    pub(super) fn pop(&mut self) -> Option<(u64, u32)> {
        let top = self.peek()?;
        self.remove(0);
        Some(top)
    }

    fn remove(&mut self, i: usize) {
        let last = self.heap.len() - 1;
        self.pos[self.heap[i].1 as usize] = ABSENT;
        if i != last {
            self.heap.swap(i, last);
            self.heap.pop();
            self.pos[self.heap[i].1 as usize] = i as u32;
            // the entry moved in from the end may belong above or below
            self.up(i);
            self.down(i);
        } else {
            self.heap.pop();
        }
    }

    fn up(&mut self, mut i: usize) {
        let e = self.heap[i];
        while i > 0 {
            let p = (i - 1) / 2;
            if self.heap[p] >= e {
                break;
            }
            self.heap[i] = self.heap[p];
            self.pos[self.heap[i].1 as usize] = i as u32;
            i = p;
        }
        self.heap[i] = e;
        self.pos[e.1 as usize] = i as u32;
    }

    fn down(&mut self, mut i: usize) {
        let n = self.heap.len();
        let e = self.heap[i];
        loop {
            let l = 2 * i + 1;
            if l >= n {
                break;
            }
            let c = if l + 1 < n && self.heap[l + 1] > self.heap[l] {
                l + 1
            } else {
                l
            };
            if self.heap[c] <= e {
                break;
            }
            self.heap[i] = self.heap[c];
            self.pos[self.heap[i].1 as usize] = i as u32;
            i = c;
        }
        self.heap[i] = e;
        self.pos[e.1 as usize] = i as u32;
    }

    /// Whether every entry sits below its parent and is where `pos` says
    /// (for tests).
    #[cfg(test)]
    fn sane(&self) -> bool {
        self.heap.iter().enumerate().all(|(i, e)| {
            self.pos[e.1 as usize] == i as u32 && (i == 0 || self.heap[(i - 1) / 2] >= *e)
        }) && self.pos.iter().filter(|&&p| p != ABSENT).count() == self.heap.len()
    }
}

#[cfg(test)]
mod tests {
    use super::Queue;
    use std::collections::BTreeMap;

    /// Against a sorted map as the oracle: random sets, changes, removals
    /// and pops (a seeded generator, so a failure repeats).
    #[test]
    fn pops_what_a_sorted_map_would() {
        let mut q = Queue::default();
        let mut oracle: BTreeMap<u32, u64> = BTreeMap::new();
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = |n: u64| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s % n
        };
        for step in 0..200_000 {
            let t = rnd(500) as u32;
            match rnd(10) {
                0..=5 => {
                    let k = rnd(1000);
                    q.set(t, Some(k));
                    oracle.insert(t, k);
                }
                6..=7 => {
                    q.set(t, None);
                    oracle.remove(&t);
                }
                _ => {
                    let want = oracle.iter().map(|(&t, &k)| (k, t)).max();
                    assert_eq!(q.pop(), want, "step {step}");
                    if let Some((_, t)) = want {
                        oracle.remove(&t);
                    }
                }
            }
            if step % 997 == 0 {
                assert!(q.sane(), "step {step}");
            }
        }
    }
}
