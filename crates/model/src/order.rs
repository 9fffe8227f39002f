//! The order in which a run visits its `n` equal positions.
//!
//! A slow bias wander projects onto the signal's first harmonic when the positions are visited
//! in one sweep: a linear drift `k` over a run of length `T` biases the plain fit by about
//! `k T / (pi H)`. Orders that put the first harmonic at high frequency in time cancel it:
//! forward-then-back exactly (each position twice, symmetric in time), opposite pairs that
//! alternate their direction almost (and half their moves are small steps).

/// Most visits a listed order holds (it lives in the firmware's configuration, in RAM).
pub const MAX_VISITS: usize = 256;

/// A visiting order over `n` equal positions `k * 360 / n`.
// The list lives inline so that a run's configuration stays `Copy` without an allocator.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Order {
    /// `0, 1, ..., n-1`: one sweep.
    Sequential,
    /// `0, ..., n-1, n-1, ..., 0`: every position twice, `2n` dwells.
    ForwardBack,
    /// `0, n/2, 1, n/2+1, ...`: each position and then its opposite (needs an even `n`).
    OppositePairs,
    /// `0, n/2, n/2+1, 1, 2, n/2+2, ...`: opposite pairs whose direction alternates, so that
    /// every other move is a small step (needs an even `n`).
    AlternatingPairs,
    /// The even positions, then the odd ones.
    Interleaved,
    /// Any sequence of position numbers below `n` (repeats allowed).
    List(VisitList),
}

/// How a run covers its positions when not evenly ([`Order::uneven`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Uneven {
    /// Positions visited at least once.
    pub visited: u16,
    /// The lowest position never visited.
    pub first_missed: Option<u16>,
    /// Fewest and most visits of one position.
    pub least: u16,
    pub most: u16,
}

impl Uneven {
    /// A warning for a person, through `write_str` alone (no `core::fmt` on the MCU).
    pub fn write_message<W: core::fmt::Write>(&self, w: &mut W, n: u16) -> core::fmt::Result {
        let num = |w: &mut W, v: u16| crate::text::write_u64(w, v as u64);
        w.write_str("the order visits ")?;
        num(w, self.visited)?;
        w.write_str(" of the ")?;
        num(w, n)?;
        w.write_str(" positions")?;
        if let Some(p) = self.first_missed {
            w.write_str(" (never position ")?;
            num(w, p)?;
            w.write_str(")")?;
        }
        w.write_str(", each ")?;
        num(w, self.least)?;
        w.write_str(" to ")?;
        num(w, self.most)?;
        w.write_str(" times: the fit takes it, but a drift or a slow wander cancels only over positions visited evenly")
    }
}

/// A listed order: position numbers in visiting order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VisitList {
    len: u16,
    idx: [u16; MAX_VISITS],
}

/// Why an order cannot be used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum OrderError {
    /// Not a named order and not a comma-separated list of position numbers.
    Unknown,
    /// A list entry is not a number.
    BadEntry { at: u16 },
    /// More than [`MAX_VISITS`] entries.
    TooLong,
    /// A listed position is not below `n`.
    OutOfRange { at: u16, position: u16, n: u16 },
    /// A listed order with no entries.
    Empty,
    /// Opposite pairs need an even number of positions.
    OddPositions,
    /// A listed order that visits fewer than three different positions: Eq. 7's `C`, `A` and
    /// `B` need three.
    FewPositions,
    /// A listed order of fewer than four visits: the fit's three terms leave no residual for
    /// a sigma (a named order's run has at least four positions).
    FewVisits,
}

impl OrderError {
    /// What is wrong, for a person; through `write_str` alone (no `core::fmt` on the MCU).
    pub fn write_message<W: core::fmt::Write>(&self, w: &mut W) -> core::fmt::Result {
        let num = |w: &mut W, v: u16| crate::text::write_u64(w, v as u64);
        match *self {
            OrderError::Unknown => {
                w.write_str("not one of")?;
                for n in NAMES {
                    w.write_char(' ')?;
                    w.write_str(n)?;
                }
                w.write_str(" and not a list of position numbers")
            }
            // Entries are counted from 1 for a person; positions from 0, as everywhere.
            OrderError::BadEntry { at } => {
                w.write_str("entry ")?;
                num(w, at.saturating_add(1))?;
                w.write_str(" of the list is not a position number")
            }
            OrderError::TooLong => {
                w.write_str("a listed order holds at most ")?;
                num(w, MAX_VISITS as u16)?;
                w.write_str(" visits")
            }
            OrderError::OutOfRange { at, position, n } => {
                w.write_str("entry ")?;
                num(w, at.saturating_add(1))?;
                w.write_str(" of the list, position ")?;
                num(w, position)?;
                w.write_str(", is not below n = ")?;
                num(w, n)
            }
            OrderError::Empty => w.write_str("the listed order is empty"),
            OrderError::OddPositions => w.write_str("paired orders need an even number of positions"),
            OrderError::FewPositions => w.write_str("fewer than 3 different positions listed"),
            OrderError::FewVisits => {
                w.write_str("fewer than 4 visits listed: the fit's 3 terms leave no residual for a sigma")
            }
        }
    }
}

impl core::fmt::Display for OrderError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        self.write_message(f)
    }
}

/// Whether a list visits fewer than three different positions.
fn fewer_than_three(list: &[u16]) -> bool {
    let mut seen = [u16::MAX; 2];
    for &p in list {
        if !seen.contains(&p) {
            match seen.iter().position(|&s| s == u16::MAX) {
                Some(free) => seen[free] = p,
                None => return false,
            }
        }
    }
    true
}

/// A position number as `u16`'s `FromStr` reads it (`[+]digits`), without that code on the MCU.
fn position_number(word: &[u8]) -> Option<u16> {
    let digits = word.strip_prefix(b"+").unwrap_or(word);
    if digits.is_empty() {
        return None;
    }
    digits.iter().try_fold(0u16, |v, &b| {
        let d = (b as char).to_digit(10)?;
        v.checked_mul(10)?.checked_add(d as u16)
    })
}

/// The names [`Order::parse`] takes, in the order of [`Order::NAMED`].
pub const NAMES: [&str; 5] = [
    "sequential",
    "forward-back",
    "opposite-pairs",
    "alternating-pairs",
    "interleaved",
];

impl Order {
    /// The named orders.
    pub const NAMED: [Order; 5] = [
        Order::Sequential,
        Order::ForwardBack,
        Order::OppositePairs,
        Order::AlternatingPairs,
        Order::Interleaved,
    ];

    /// The named order `i` of [`Order::NAMED`]. (A match, not an index into `NAMED`: every
    /// `Order` is as large as a full listed order, so the table takes 2.5 KiB of the
    /// firmware's flash.)
    pub fn named(i: usize) -> Option<Order> {
        Some(match i {
            0 => Order::Sequential,
            1 => Order::ForwardBack,
            2 => Order::OppositePairs,
            3 => Order::AlternatingPairs,
            4 => Order::Interleaved,
            _ => return None,
        })
    }

    /// Where a named order is in [`Order::NAMED`]; `None` for a listed one.
    pub fn named_index(&self) -> Option<usize> {
        match self {
            Order::Sequential => Some(0),
            Order::ForwardBack => Some(1),
            Order::OppositePairs => Some(2),
            Order::AlternatingPairs => Some(3),
            Order::Interleaved => Some(4),
            Order::List(_) => None,
        }
    }

    /// A name of [`NAMES`] (case-insensitive) or a comma-separated list such as `0,36,37,1`.
    pub fn parse(s: &str) -> Result<Order, OrderError> {
        let s = s.trim_ascii();
        if let Some(o) = NAMES
            .iter()
            .position(|n| n.eq_ignore_ascii_case(s))
            .and_then(Order::named)
        {
            return Ok(o);
        }
        if !s.starts_with(|c: char| c.is_ascii_digit()) {
            return Err(OrderError::Unknown);
        }
        let mut list = VisitList::EMPTY;
        list.extend(s)?;
        Ok(Order::List(list))
    }

    pub fn name(&self) -> &'static str {
        match self.named_index() {
            Some(i) => NAMES[i],
            None => "list",
        }
    }

    /// Whether the order can visit `n` positions.
    pub fn check(&self, n: u16) -> Result<(), OrderError> {
        match self {
            Order::OppositePairs | Order::AlternatingPairs if !n.is_multiple_of(2) => Err(OrderError::OddPositions),
            Order::List(l) if l.len == 0 => Err(OrderError::Empty),
            Order::List(l) => match l.as_slice().iter().position(|&p| p >= n) {
                Some(at) => Err(OrderError::OutOfRange {
                    at: at as u16,
                    position: l.idx[at],
                    n,
                }),
                None if fewer_than_three(l.as_slice()) => Err(OrderError::FewPositions),
                None if l.len < 4 => Err(OrderError::FewVisits),
                None => Ok(()),
            },
            _ => Ok(()),
        }
    }

    /// Dwells of a run over `n` positions.
    pub fn visits(&self, n: u16) -> u16 {
        match self {
            Order::ForwardBack => n.saturating_mul(2),
            Order::List(l) => l.len,
            _ => n,
        }
    }

    /// The position number of visit `j` (`j < visits(n)`, and [`Order::check`] passed).
    pub fn position(&self, n: u16, j: u16) -> u16 {
        let half = n / 2;
        match self {
            Order::Sequential => j,
            Order::ForwardBack if j < n => j,
            Order::ForwardBack => (2 * n - 1).saturating_sub(j),
            Order::OppositePairs => j / 2 + if j % 2 == 1 { half } else { 0 },
            Order::AlternatingPairs => {
                let (pair, second) = (j / 2, j % 2 == 1);
                // Odd pairs start from the far side, so the motor alternates half turns and
                // small steps and a drift's effect on the pair difference alternates in sign.
                if second != (pair % 2 == 1) { pair + half } else { pair }
            }
            Order::Interleaved => {
                let evens = n.div_ceil(2);
                if j < evens { 2 * j } else { 2 * (j - evens) + 1 }
            }
            Order::List(l) => l.idx[j as usize],
        }
    }

    /// The positions of a run over `n` positions, in visiting order.
    pub fn positions(&self, n: u16) -> impl Iterator<Item = u16> + '_ {
        (0..self.visits(n)).map(move |j| self.position(n, j))
    }

    /// How unevenly a run over `n` positions visits them; `None` when it visits each equally
    /// often (every named order does). Eq. 7 takes any three positions, but a drift or a slow
    /// wander cancels only over an even coverage, so a list that misses or repeats positions
    /// is worth a word to whoever gave it. Lists only: the named orders are even (tested).
    /// `n * visits` steps, without a table (no allocator on the MCU).
    pub fn uneven(&self, n: u16) -> Option<Uneven> {
        let Order::List(l) = self else { return None };
        let count = |p: u16| l.as_slice().iter().filter(|&&q| q == p).count() as u16;
        let mut u = Uneven {
            visited: 0,
            first_missed: None,
            least: u16::MAX,
            most: 0,
        };
        for p in 0..n {
            let c = count(p);
            if c == 0 {
                u.first_missed.get_or_insert(p);
            } else {
                u.visited += 1;
            }
            u.least = u.least.min(c);
            u.most = u.most.max(c);
        }
        (u.least != u.most).then_some(u)
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for VisitList {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(f, "{} listed visits", self.len)
    }
}

impl VisitList {
    pub const EMPTY: VisitList = VisitList {
        len: 0,
        idx: [0; MAX_VISITS],
    };

    pub fn as_slice(&self) -> &[u16] {
        &self.idx[..self.len as usize]
    }

    /// Appends the entries of a comma-separated list (for lists longer than one line).
    pub fn extend(&mut self, csv: &str) -> Result<(), OrderError> {
        for word in csv.split(',') {
            let at = self.len;
            let p = position_number(word.trim_ascii().as_bytes()).ok_or(OrderError::BadEntry { at })?;
            self.push(p)?;
        }
        Ok(())
    }

    pub fn push(&mut self, position: u16) -> Result<(), OrderError> {
        let slot = self.idx.get_mut(self.len as usize).ok_or(OrderError::TooLong)?;
        *slot = position;
        self.len += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Float;
    use std::vec::Vec;

    fn seq(o: &Order, n: u16) -> Vec<u16> {
        o.positions(n).collect()
    }

    #[test]
    fn named_orders_visit_what_they_say() {
        assert_eq!(seq(&Order::Sequential, 4), [0, 1, 2, 3]);
        assert_eq!(seq(&Order::ForwardBack, 3), [0, 1, 2, 2, 1, 0]);
        assert_eq!(seq(&Order::OppositePairs, 8), [0, 4, 1, 5, 2, 6, 3, 7]);
        assert_eq!(seq(&Order::AlternatingPairs, 8), [0, 4, 5, 1, 2, 6, 7, 3]);
        assert_eq!(seq(&Order::Interleaved, 5), [0, 2, 4, 1, 3]);
        assert_eq!(Order::OppositePairs.check(7), Err(OrderError::OddPositions));
    }

    #[test]
    fn a_list_needs_three_different_positions() {
        let list = |s: &str| Order::parse(s).unwrap().check(8);
        for few in ["0", "0,4,4,0", "3,3,3,3,5"] {
            assert_eq!(list(few), Err(OrderError::FewPositions), "{few}");
        }
        assert_eq!(list("0,4,1"), Err(OrderError::FewVisits));
        for enough in ["0,4,1,1", "0,0,0,4,4,2", "7,6,5,4,3,2,1,0"] {
            assert_eq!(list(enough), Ok(()), "{enough}");
        }
    }

    #[test]
    fn every_named_order_visits_every_position_equally_often() {
        for o in Order::NAMED {
            for n in (4..=720).step_by(2) {
                let mut count = std::vec![0u16; n as usize];
                o.positions(n).for_each(|p| count[p as usize] += 1);
                let each = o.visits(n) / n;
                assert!(count.iter().all(|&c| c == each), "{} at n = {n}", o.name());
            }
        }
    }

    #[test]
    fn an_uneven_list_says_how_and_an_even_one_nothing() {
        let uneven = |s: &str, n: u16| Order::parse(s).unwrap().uneven(n);
        assert_eq!(uneven("0,1,2,3,3,2,1,0", 4), None);
        let u = uneven("0,1,2,2,5", 6).unwrap();
        assert_eq!(
            u,
            Uneven {
                visited: 4,
                first_missed: Some(3),
                least: 0,
                most: 2
            }
        );
        let mut msg = std::string::String::new();
        u.write_message(&mut msg, 6).unwrap();
        assert!(
            msg.starts_with("the order visits 4 of the 6 positions (never position 3), each 0 to 2 times"),
            "{msg}"
        );
        let all_once_one_twice = uneven("0,1,2,3,0", 4).unwrap();
        assert_eq!(
            (
                all_once_one_twice.first_missed,
                all_once_one_twice.least,
                all_once_one_twice.most
            ),
            (None, 1, 2)
        );
    }

    /// The first-harmonic projection of a unit linear drift, relative to a sequential sweep's.
    fn drift_coupling(o: &Order, n: u16) -> f64 {
        let proj = |o: &Order| {
            let (mut c, mut s) = (0.0, 0.0);
            for (t, p) in o.positions(n).enumerate() {
                let g = p as f64 * 2.0 * core::f64::consts::PI / n as f64;
                c += t as f64 * Float::cos(g);
                s += t as f64 * Float::sin(g);
            }
            Float::hypot(c, s) / o.visits(n) as f64
        };
        proj(o) / proj(&Order::Sequential)
    }

    #[test]
    fn balanced_orders_cancel_a_linear_drift() {
        for n in [8u16, 36, 72, 180] {
            assert!(drift_coupling(&Order::ForwardBack, n) < 1e-9);
            let pairs = drift_coupling(&Order::OppositePairs, n);
            assert!(pairs < 2.01 / n as f64, "n = {n}: {pairs}");
            let alternating = drift_coupling(&Order::AlternatingPairs, n);
            assert!(alternating < 7.0 / (n as f64 * n as f64), "n = {n}: {alternating}");
            let inter = drift_coupling(&Order::Interleaved, n);
            assert!((0.4..0.6).contains(&inter), "n = {n}: {inter}");
        }
    }

    #[test]
    fn position_numbers_read_as_u16_reads_them() {
        let mut rng = crate::rng::Rng::new(4);
        let alphabet = b"0123456789+- .x";
        for _ in 0..100_000 {
            let len = (rng.next_u64() % 8) as usize;
            let word: std::vec::Vec<u8> = (0..len)
                .map(|_| alphabet[(rng.next_u64() % alphabet.len() as u64) as usize])
                .collect();
            let text = core::str::from_utf8(&word).unwrap();
            assert_eq!(position_number(&word), text.parse::<u16>().ok(), "{text:?}");
        }
        assert_eq!(position_number(b"65535"), Some(65535));
        assert_eq!(position_number(b"0000000000012"), Some(12));
    }

    #[test]
    fn every_error_says_what_is_wrong() {
        let says = |e: OrderError| std::format!("{e}");
        assert_eq!(
            says(OrderError::Unknown),
            "not one of sequential forward-back opposite-pairs alternating-pairs interleaved and not a list of position numbers"
        );
        assert_eq!(
            says(OrderError::BadEntry { at: 2 }),
            "entry 3 of the list is not a position number"
        );
        assert_eq!(says(OrderError::TooLong), "a listed order holds at most 256 visits");
        assert_eq!(
            says(OrderError::OutOfRange {
                at: 3,
                position: 400,
                n: 72
            }),
            "entry 4 of the list, position 400, is not below n = 72"
        );
        assert_eq!(says(OrderError::Empty), "the listed order is empty");
        assert_eq!(
            says(OrderError::FewPositions),
            "fewer than 3 different positions listed"
        );
        assert_eq!(
            says(OrderError::OddPositions),
            "paired orders need an even number of positions"
        );
    }

    #[test]
    fn named_orders_by_index_are_the_table() {
        for (i, o) in Order::NAMED.iter().enumerate() {
            assert_eq!(Order::named(i), Some(*o));
            assert_eq!(o.named_index(), Some(i));
            assert_eq!(Order::parse(NAMES[i]), Ok(*o));
            assert_eq!(o.name(), NAMES[i]);
        }
        assert_eq!(Order::named(5), None);
        let list = Order::parse("0,1").unwrap();
        assert_eq!((list.named_index(), list.name()), (None, "list"));
    }

    #[test]
    fn lists_parse_and_every_bad_list_says_where() {
        let o = Order::parse("0, 2,1,3").unwrap();
        assert_eq!(seq(&o, 4), [0, 2, 1, 3]);
        assert_eq!(o.check(4), Ok(()));
        assert_eq!(
            o.check(3),
            Err(OrderError::OutOfRange {
                at: 3,
                position: 3,
                n: 3
            })
        );
        assert_eq!(Order::parse("Opposite-Pairs"), Ok(Order::OppositePairs));
        assert_eq!(Order::parse("alternating-pairs"), Ok(Order::AlternatingPairs));
        assert_eq!(Order::parse("spiral"), Err(OrderError::Unknown));
        assert_eq!(Order::parse("0,1,x"), Err(OrderError::BadEntry { at: 2 }));
        assert_eq!(Order::parse("0,,1"), Err(OrderError::BadEntry { at: 1 }));
        assert_eq!(Order::parse("0,+1, 2 ,65535"), Order::parse("0,1,2,65535"));
        for bad in ["65536", "-0", "1.0", "+", "++1", "1+", "0x1", "1_0", "\u{661}"] {
            assert_eq!(
                Order::parse(&std::format!("0,{bad}")),
                Err(OrderError::BadEntry { at: 1 }),
                "{bad}"
            );
        }
        let mut l = VisitList::EMPTY;
        for _ in 0..MAX_VISITS {
            l.push(1).unwrap();
        }
        assert_eq!(l.push(1), Err(OrderError::TooLong));
        assert_eq!(Order::List(VisitList::EMPTY).check(4), Err(OrderError::Empty));
    }
}
