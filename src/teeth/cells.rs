//! The cell index of an outline ([`super::shape::Shape`]): occupied grid cells `(cx, cy)` → the
//! run `(start, len)` of their segments in an open-addressing table, and a dense map of the
//! coarse blocks farther than one cell from the outline with their side.
//!
//! Written by hand rather than taken from a general hash map because it sits in the innermost
//! loop of the mesh check (up to nine look-ups per clearance query, about a million queries per
//! verified pair): the key is packed into one `u64`, the table is kept at most a quarter full so
//! that a miss — the common case, most neighbour cells are empty — ends at the first or second
//! slot, and a slot is 16 bytes (key and run), so a probe touches one cache line.

use crate::math::Point;
/// Occupied cells → segment runs. Keys are cell coordinates within ±2³¹.
#[derive(Debug, Clone)]
pub(crate) struct CellTable {
    /// `(key, start, len)`; `key == EMPTY` marks a free slot.
    slots: Vec<(u64, u32, u32)>,
    /// `slots.len() − 1` (a power of two less one).
    mask: usize,
    /// Right shift that keeps the table's index bits of the multiplicative hash.
    shift: u32,
    len: usize,
}

/// The key of no cell: `(i32::MIN, i32::MIN)`, outside the ±(2³¹ − 1) cells an outline may span.
const EMPTY: u64 = 0x8000_0000_8000_0000;

/// Packs `(cx, cy)` into one key, the low 32 bits of each (a cell beyond ±(2³¹ − 1) would be an
/// outline wider than 2³¹ cells, far beyond any gear).
fn pack((cx, cy): (i64, i64)) -> u64 {
    (u64::from(cx as u32) << 32) | u64::from(cy as u32)
}

impl CellTable {
    /// An empty table sized for `cells` entries (at most a quarter full).
    pub(crate) fn with_cells(cells: usize) -> Self {
        let cap = (4 * cells.max(1)).next_power_of_two();
        Self {
            slots: vec![(EMPTY, 0, 0); cap],
            mask: cap - 1,
            shift: 64 - cap.trailing_zeros(),
            len: 0,
        }
    }

    fn home(&self, key: u64) -> usize {
        // Fibonacci hashing: the golden-ratio multiplier spreads neighbouring cells.
        (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> self.shift) as usize
    }

    /// Inserts or replaces the run of `cell`.
    pub(crate) fn insert(&mut self, cell: (i64, i64), run: (u32, u32)) {
        let key = pack(cell);
        let mut i = self.home(key);
        loop {
            let slot = &mut self.slots[i];
            if slot.0 == key || slot.0 == EMPTY {
                if slot.0 == EMPTY {
                    self.len += 1;
                }
                *slot = (key, run.0, run.1);
                return;
            }
            i = (i + 1) & self.mask;
        }
    }

    /// The run of `cell`, if occupied.
    #[inline]
    pub(crate) fn get(&self, cell: (i64, i64)) -> Option<(u32, u32)> {
        let key = pack(cell);
        let mut i = self.home(key);
        loop {
            let (k, start, len) = self.slots[i];
            if k == key {
                return Some((start, len));
            }
            if k == EMPTY {
                return None;
            }
            i = (i + 1) & self.mask;
        }
    }

    /// Number of occupied cells.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// Every occupied cell and its run (in table order).
    pub(crate) fn iter(&self) -> impl Iterator<Item = ((i64, i64), (u32, u32))> + '_ {
        self.slots
            .iter()
            .filter(|s| s.0 != EMPTY)
            .map(|&(k, start, len)| {
                (
                    (
                        i64::from((k >> 32) as u32 as i32),
                        i64::from(k as u32 as i32),
                    ),
                    (start, len),
                )
            })
    }
}

/// Side of a coarse block of cells that no segment comes within one fine cell of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Side {
    /// Some segment may be within one fine cell of a point of the block: look it up.
    Near,
    /// Every point of the block is inside the outline, farther than one fine cell from it.
    Inside,
    /// Every point of the block is outside the outline, farther than one fine cell from it.
    Outside,
}

/// A dense map of coarse blocks (`2^shift` × `2^shift` fine cells) over the outline's box,
/// telling for each block whether a query in it can be near the outline, and if not, on which
/// side it is — so that a far query costs one array read instead of nine table look-ups and a
/// crossing count.
///
/// Exact: a point within one fine cell of a segment lies in a fine cell next to (3 × 3) one
/// the segment occupies; blocks holding no such cell are far, and a boundary-free run of far
/// blocks along a row is on one side, found by one crossing test at its first block's centre.
#[derive(Debug, Clone)]
pub(crate) struct FarMap {
    /// Fine-cell coordinates of the map's first block's first cell.
    origin: (i64, i64),
    shift: u32,
    nx: usize,
    ny: usize,
    sides: Vec<Side>,
}

impl FarMap {
    /// Blocks over the occupied fine cells `occupied` (coordinates in cells of `cell_mm`), at
    /// most about 2²² of them; `inside(x)` is the exact crossing test of a point (mm).
    pub(crate) fn new(
        occupied: &[(i64, i64)],
        cell_mm: f64,
        inside: impl Fn(Point) -> bool,
    ) -> Self {
        let (lo, hi) = occupied.iter().fold(
            ((i64::MAX, i64::MAX), (i64::MIN, i64::MIN)),
            |(l, h), &(x, y)| ((l.0.min(x), l.1.min(y)), (h.0.max(x), h.1.max(y))),
        );
        if lo.0 > hi.0 {
            return Self {
                origin: (0, 0),
                shift: 0,
                nx: 0,
                ny: 0,
                sides: Vec::new(),
            };
        }
        // The box of the occupied cells and their neighbours.
        let (lo, hi) = ((lo.0 - 1, lo.1 - 1), (hi.0 + 1, hi.1 + 1));
        let (wx, wy) = ((hi.0 - lo.0 + 1) as u64, (hi.1 - lo.1 + 1) as u64);
        let mut shift = 1;
        while (wx >> shift).saturating_add(1) * (wy >> shift).saturating_add(1) > 1 << 21 {
            shift += 1;
        }
        let (nx, ny) = (((wx >> shift) + 1) as usize, ((wy >> shift) + 1) as usize);
        let mut sides = vec![Side::Outside; nx * ny];
        let mut near = vec![false; nx * ny];
        for &(x, y) in occupied {
            for (dx, dy) in [(-1, -1), (-1, 1), (1, -1), (1, 1)] {
                let (bx, by) = (
                    ((x + dx - lo.0) >> shift) as usize,
                    ((y + dy - lo.1) >> shift) as usize,
                );
                near[by * nx + bx] = true;
            }
        }
        let size = cell_mm * (1u64 << shift) as f64;
        for by in 0..ny {
            let mut side = None;
            for bx in 0..nx {
                let k = by * nx + bx;
                if near[k] {
                    sides[k] = Side::Near;
                    side = None;
                    continue;
                }
                let s = *side.get_or_insert_with(|| {
                    let centre = Point::new(
                        lo.0 as f64 * cell_mm + (bx as f64 + 0.5) * size,
                        lo.1 as f64 * cell_mm + (by as f64 + 0.5) * size,
                    );
                    if inside(centre) {
                        Side::Inside
                    } else {
                        Side::Outside
                    }
                });
                sides[k] = s;
            }
        }
        Self {
            origin: lo,
            shift,
            nx,
            ny,
            sides,
        }
    }

    /// Side of the block holding fine cell `(cx, cy)` (outside the map: [`Side::Outside`]).
    #[inline]
    pub(crate) fn side(&self, (cx, cy): (i64, i64)) -> Side {
        let (x, y) = (
            cx.wrapping_sub(self.origin.0),
            cy.wrapping_sub(self.origin.1),
        );
        if x < 0 || y < 0 {
            return Side::Outside;
        }
        let (bx, by) = ((x >> self.shift) as usize, (y >> self.shift) as usize);
        if bx >= self.nx || by >= self.ny {
            return Side::Outside;
        }
        self.sides[by * self.nx + bx]
    }
}

#[cfg(test)]
mod tests {
    use super::CellTable;

    #[test]
    fn round_trips_cells_around_the_origin_and_misses_the_rest() {
        let cells: Vec<(i64, i64)> = (-40..40)
            .flat_map(|x| (-3..3).map(move |y| (x * 7 - 1, y - 1)))
            .collect();
        let mut t = CellTable::with_cells(cells.len());
        for (k, &c) in cells.iter().enumerate() {
            t.insert(c, (k as u32, 1));
        }
        assert_eq!(t.len(), cells.len());
        for (k, &c) in cells.iter().enumerate() {
            assert_eq!(t.get(c), Some((k as u32, 1)), "{c:?}");
            assert_eq!(t.get((c.0 + 1, c.1)), None);
        }
        assert!(cells.contains(&(-1, -1)));
        let mut back: Vec<(i64, i64)> = t.iter().map(|(c, _)| c).collect();
        back.sort_unstable();
        let mut want = cells.clone();
        want.sort_unstable();
        assert_eq!(back, want);
    }
}
