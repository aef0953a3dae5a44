#[path = "../tests/common/mod.rs"]
mod common;
use std::time::Instant;
fn main() {
    for n in [1, 2, 1, 2, 1, 2] {
        tinmerge::tin::par::set_threads(n);
        let t0 = Instant::now();
        let tin = common::dem_tin();
        let el = t0.elapsed();
        let b = tinmerge::tin::layout::encode(&tin);
        println!(
            "threads {n} build {:?} hash {:x}",
            el,
            tinmerge::tin::layout::content_hash(&b)
        );
    }
}
