//! Independent pieces of work spread over the cores.

/// `one(i)` for every `i` in `0..count`, in that order, the items dealt round the cores. A
/// panic in one is raised again here.
pub fn each<T: Send>(count: usize, one: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let threads = std::thread::available_parallelism()
        .map_or(1, |c| c.get())
        .min(count.max(1));
    if threads == 1 {
        return (0..count).map(one).collect();
    }
    let one = &one;
    let mut numbered: Vec<(usize, T)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|w| s.spawn(move || (w..count).step_by(threads).map(|i| (i, one(i))).collect::<Vec<_>>()))
            .collect();
        workers
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    numbered.sort_by_key(|(i, _)| *i);
    numbered.into_iter().map(|(_, t)| t).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_item_comes_back_once_in_its_place() {
        for count in [0, 1, 2, 3, 17] {
            let got = each(count, |i| (i, std::thread::current().id()));
            assert_eq!(
                got.iter().map(|(i, _)| *i).collect::<Vec<_>>(),
                (0..count).collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn a_panic_in_one_item_is_not_lost() {
        let r = std::panic::catch_unwind(|| each(8, |i| assert!(i != 5, "item 5")));
        assert!(r.is_err());
    }
}
