//! Incremental shortest paths over the memory's grid: D* Lite (Koenig and Likhachev, 2002),
//! searching from the goal back toward the agent. Like the memory it serves, it goes beyond
//! seed 000 §3.1, which steers without a map.
//!
//! Every cell holds `g`, its distance to the goal as last settled, and `rhs`, the best of its
//! moves' costs plus their targets' `g`; a cell whose two differ is *inconsistent* and waits
//! in the queue, ordered by the key `(min(g, rhs) + h(agent, cell) + km, min(g, rhs))` (`h` the
//! octile distance, `km` the sum of the agent's moves, so keys queued before a move stay lower
//! bounds). Settling a cell (the agent's, or the end of the kept way) takes queued cells in key
//! order until none ahead of it is left: the first time that is a plain A* from the goal, and
//! afterwards a newly marked cell costs only the cells whose distance it changes (Koenig and
//! Likhachev's theorem: the cell's `g` is then its exact distance, and stepping to the move of
//! least cost plus `g` follows a shortest way).
//!
//! Costs are integers ([`UNIT`] per cell side), so sums do not depend on the order they were
//! added in and a repaired distance equals a fresh search's exactly (property-tested below
//! against a from-scratch search). The queue orders by key, then cell index: the same marks in
//! the same order give the same ways, bit for bit. `g` and `rhs` are stored complemented, so a
//! fresh grid is zeroed memory and pages the search never reaches are never touched.

/// A cell's bit: a ray hit an obstacle in it.
pub(super) const MARKED: u8 = 0x10;

/// A cell's bit: it cannot be crossed.
pub(super) const HARD: u8 = 0x20;

/// A cell's bits holding its band of the margin.
pub(super) const BAND: u8 = 0x03;

/// A cell's bit: only the body's narrowest stance crosses it (a character side-on): it lies
/// within the closing distance of the body's walking disc but not of its narrowest stance.
pub(super) const NARROW: u8 = 0x04;

/// A cell's bits that give the cost of a step into it.
pub(super) const COST: u8 = BAND | NARROW;

/// Cost of a straight step into a cell outside the margin (a cell side).
pub(super) const UNIT: u32 = 256;

/// Cost of a diagonal step into a cell outside the margin (256·√2, rounded).
const DIAGONAL: u32 = 362;

/// No way.
const INF: u32 = u32::MAX;

/// The eight steps: offsets and whether the step is diagonal.
pub(super) const STEPS: [(i64, i64, bool); 8] = [
    (1, 0, false),
    (-1, 0, false),
    (0, 1, false),
    (0, -1, false),
    (1, 1, true),
    (1, -1, true),
    (-1, 1, true),
    (-1, -1, true),
];

/// The moves a way from cell `start` to cell `goal` may make over the cells.
#[derive(Clone, Copy)]
pub(super) struct Moves<'a> {
    pub cells: &'a [u8],
    pub nx: i64,
    pub ny: i64,
    pub goal: usize,
    pub start: (i64, i64),
    /// Closed cells the agent may cross to get out of the inflation it stands in: those
    /// within this many cells of the start.
    pub escape: i64,
}

impl Moves<'_> {
    /// The cell that `step` from cell `(x, y)` enters, if a way may take it.
    #[inline(always)]
    pub fn step(&self, x: i64, y: i64, (dx, dy, diagonal): (i64, i64, bool)) -> Option<usize> {
        let (mx, my) = (x + dx, y + dy);
        if mx < 0 || my < 0 || mx >= self.nx || my >= self.ny {
            return None;
        }
        let m = (my * self.nx + mx) as usize;
        (self.enterable(m, mx, my) && !(diagonal && self.squeezed(x, y, mx, my))).then_some(m)
    }

    /// Whether a way may enter cell `m` at `(mx, my)`. The agent may stand in inflated cells
    /// (close to a wall): it may leave them, but closed cells are crossed only within the
    /// disc's reach of where it stands, never through a wall.
    #[inline(always)]
    pub fn enterable(&self, m: usize, mx: i64, my: i64) -> bool {
        let cell = self.cells[m];
        cell & HARD == 0
            || m == self.goal
            || (cell & MARKED == 0 && (mx - self.start.0).abs().max((my - self.start.1).abs()) <= self.escape)
    }

    /// Whether a diagonal step from `(x, y)` to `(mx, my)` squeezes between two closed cells.
    #[inline(always)]
    fn squeezed(&self, x: i64, y: i64, mx: i64, my: i64) -> bool {
        self.cells[(y * self.nx + mx) as usize] & self.cells[(my * self.nx + x) as usize] & HARD != 0
    }
}

/// The costs of a straight and of a diagonal step into a cell of each band, for a clearance
/// margin costing `margin_cost` extra per cell side in its innermost band (`bands` bands), and
/// `narrow_cost` more into a [`NARROW`] cell; indexed by the cell's [`COST`] bits.
pub(super) fn step_costs(margin_cost: f64, bands: u8, narrow_cost: f64) -> [[u32; 2]; COST as usize + 1] {
    std::array::from_fn(|k| {
        let band = k & usize::from(BAND);
        let narrow = if k & usize::from(NARROW) != 0 { narrow_cost.max(0.0) } else { 0.0 };
        let extra = 1.0 + margin_cost.max(0.0) * band.min(usize::from(bands)) as f64 / f64::from(bands.max(1)) + narrow;
        let cost = |base: u32| (f64::from(base) * extra).round().min(f64::from(INF / 4)) as u32;
        [cost(UNIT), cost(DIAGONAL)]
    })
}

/// The octile distance between two cells in cost units (a lower bound on every way's cost).
#[inline(always)]
fn octile(a: (i64, i64), b: (i64, i64)) -> u64 {
    let (dx, dy) = ((a.0 - b.0).unsigned_abs(), (a.1 - b.1).unsigned_abs());
    u64::from(UNIT) * dx.max(dy) + (u64::from(DIAGONAL) - u64::from(UNIT)) * dx.min(dy)
}

/// A queued cell: its key, then its index (the order of the queue).
type Entry = (u64, u64, u32);

/// Bits of a packed entry below the key's first part: the key's second part (below 2³³, see
/// [`Replanner::key`]) and the cell's index (below 2³¹).
const INDEX_BITS: u32 = 31;

/// An [`Entry`] in one number that orders as the entry does: the key's first part, its second,
/// the cell's index.
#[inline(always)]
fn pack((k1, k2, k): Entry) -> u128 {
    debug_assert!(k2 < 1 << 33 && k < 1 << INDEX_BITS);
    (u128::from(k1) << 64) | (u128::from(k2) << INDEX_BITS) | u128::from(k)
}

/// The [`Entry`] of a [`pack`]ed one.
#[inline(always)]
fn unpack(e: u128) -> Entry {
    ((e >> 64) as u64, ((e as u64) >> INDEX_BITS), (e as u32) & ((1 << INDEX_BITS) - 1))
}

/// Children of each place in the queue's heap.
const ARITY: usize = 4;

/// The queue of inconsistent cells: a heap of [`pack`]ed entries, each place's [`ARITY`]
/// children after it, that knows where each cell is, so a cell is queued once and its key
/// changed or taken out in place. Keys are unique (they end in the cell's index), so the first
/// entry is whatever the heap's shape.
#[derive(Debug, Clone, Default)]
struct Queue {
    heap: Vec<u128>,
    /// One more than each cell's place in the heap (0: not queued).
    at: Vec<u32>,
}

impl Queue {
    fn reset(&mut self, n: usize) {
        assert!(n <= 1 << INDEX_BITS, "a grid of {n} cells is too large to search");
        self.heap.clear();
        self.at = vec![0; n];
    }

    fn first(&self) -> Option<Entry> {
        self.heap.first().map(|&e| unpack(e))
    }

    /// Queues cell `k` with `key`, or moves it to `key` if it is queued.
    fn set(&mut self, k: u32, key: (u64, u64)) {
        let e = pack((key.0, key.1, k));
        match self.at[k as usize] {
            0 => {
                self.heap.push(e);
                self.at[k as usize] = self.heap.len() as u32;
                self.up(self.heap.len() - 1);
            }
            p => {
                let i = p as usize - 1;
                let old = std::mem::replace(&mut self.heap[i], e);
                if e < old { self.up(i) } else { self.down(i) }
            }
        }
    }

    /// Takes cell `k` out of the queue if it is in it.
    fn remove(&mut self, k: u32) {
        let p = std::mem::take(&mut self.at[k as usize]);
        if p == 0 {
            return;
        }
        let i = p as usize - 1;
        let last = self.heap.pop().expect("a queued cell is in the heap");
        if i < self.heap.len() {
            let old = std::mem::replace(&mut self.heap[i], last);
            self.at[(last as u32 & ((1 << INDEX_BITS) - 1)) as usize] = i as u32 + 1;
            if last < old { self.up(i) } else { self.down(i) }
        }
    }

    /// Moves the entry at `i` up to its place: the entries above it that it goes before move
    /// down one level each, and it is written once where it stops (as swapping it up level by
    /// level would leave the heap).
    fn up(&mut self, mut i: usize) {
        let e = self.heap[i];
        while i > 0 {
            let parent = (i - 1) / ARITY;
            let pe = self.heap[parent];
            if pe <= e {
                break;
            }
            self.place(i, pe);
            i = parent;
        }
        self.place(i, e);
    }

    /// Moves the entry at `i` down to its place, as [`Queue::up`] does the other way.
    fn down(&mut self, mut i: usize) {
        let e = self.heap[i];
        let n = self.heap.len();
        loop {
            let first = ARITY * i + 1;
            if first >= n {
                break;
            }
            let mut least = first;
            let mut least_e = self.heap[first];
            for c in first + 1..(first + ARITY).min(n) {
                let ce = self.heap[c];
                if ce < least_e {
                    (least, least_e) = (c, ce);
                }
            }
            if least_e >= e {
                break;
            }
            self.place(i, least_e);
            i = least;
        }
        self.place(i, e);
    }

    /// Writes entry `e` at place `i` of the heap.
    #[inline(always)]
    fn place(&mut self, i: usize, e: u128) {
        self.heap[i] = e;
        self.at[(e as u32 & ((1 << INDEX_BITS) - 1)) as usize] = i as u32 + 1;
    }

    /// The queue of a grown grid, each cell's index changed by `moved`. The order of the cells
    /// does not change (the keys do not), so the heap keeps its shape.
    fn moved(&mut self, n: usize, moved: impl Fn(u32) -> u32) {
        assert!(n <= 1 << INDEX_BITS, "a grid of {n} cells is too large to search");
        self.at = vec![0; n];
        for (i, e) in self.heap.iter_mut().enumerate() {
            let (k1, k2, k) = unpack(*e);
            *e = pack((k1, k2, moved(k)));
            self.at[moved(k) as usize] = i as u32 + 1;
        }
    }
}

/// The state of D* Lite over a grid of `nx × ny` cells toward a fixed goal cell.
#[derive(Debug, Clone, Default)]
pub(super) struct Replanner {
    nx: usize,
    ny: usize,
    /// Whether the grid has been set up ([`Replanner::begin`]).
    ready: bool,
    goal: usize,
    /// The agent's cell, the keys' origin.
    start: (i64, i64),
    /// See [`Moves::escape`].
    escape: i64,
    costs: [[u32; 2]; COST as usize + 1],
    /// `!g` of each cell (zero: no way known).
    g: Vec<u32>,
    /// `!rhs` of each cell.
    rhs: Vec<u32>,
    open: Queue,
    /// Sum of the octile lengths of the agent's moves since the first search.
    km: u64,
    /// Cells whose state changed since the last settling.
    changed: Vec<u32>,
    /// The cell being settled (kept in the queue even where a way may not enter it).
    target: usize,
    /// Scratch: cells whose `rhs` is to be worked out again.
    touched: Vec<u32>,
    /// Stamps of the flood ([`Replanner::reaches`]).
    seen: Vec<u32>,
    stamp: u32,
    /// Cells taken from the queue so far (for tests and profiles).
    pub expanded: u64,
}

impl Replanner {
    /// A planner whose steps cost `costs` (see [`step_costs`]).
    pub fn new(costs: [[u32; 2]; COST as usize + 1]) -> Replanner {
        Replanner { costs, ..Replanner::default() }
    }

    /// Whether the grid has been set up.
    pub fn ready(&self) -> bool {
        self.ready
    }

    /// Sets up a grid of `nx × ny` cells, all unknown to the search, toward the goal cell
    /// `goal`, with the agent at `start` allowed to cross closed cells `escape` cells around it.
    pub fn begin(&mut self, nx: usize, ny: usize, goal: (i64, i64), start: (i64, i64), escape: i64) {
        let n = nx * ny;
        self.nx = nx;
        self.ny = ny;
        self.g = vec![0; n];
        self.rhs = vec![0; n];
        self.open.reset(n);
        self.changed.clear();
        self.km = 0;
        self.start = start;
        self.escape = escape;
        self.goal = goal.1 as usize * nx + goal.0 as usize;
        self.target = self.goal;
        self.ready = true;
        self.set_rhs(self.goal, 0);
        let key = self.key(self.goal);
        self.open.set(self.goal as u32, key);
    }

    /// Notes that cell `k` changed state (marked, closed or in a deeper band).
    #[inline]
    pub fn changed(&mut self, k: usize) {
        if self.ready {
            self.changed.push(k as u32);
        }
    }

    /// The grid grew: the old `old_nx × old_ny` cells now start at `(sx, sy)` in a grid of
    /// `nx × ny`, the cells around them new and free.
    pub fn grow(&mut self, old_nx: usize, old_ny: usize, nx: usize, ny: usize, (sx, sy): (usize, usize)) {
        if !self.ready {
            return;
        }
        let moved = |k: u32| -> u32 {
            let (x, y) = (k as usize % old_nx, k as usize / old_nx);
            ((y + sy) * nx + x + sx) as u32
        };
        let mut g = vec![0u32; nx * ny];
        let mut rhs = vec![0u32; nx * ny];
        for y in 0..old_ny {
            let (from, to) = (y * old_nx, (y + sy) * nx + sx);
            g[to..to + old_nx].copy_from_slice(&self.g[from..from + old_nx]);
            rhs[to..to + old_nx].copy_from_slice(&self.rhs[from..from + old_nx]);
        }
        (self.g, self.rhs) = (g, rhs);
        self.open.moved(nx * ny, moved);
        self.changed.iter_mut().for_each(|k| *k = moved(*k));
        self.goal = moved(self.goal as u32) as usize;
        self.target = moved(self.target as u32) as usize;
        self.start = (self.start.0 + sx as i64, self.start.1 + sy as i64);
        self.seen = Vec::new();
        // The new cells next to the old ones can now be stepped into from them.
        let (x0, y0, x1, y1) = (sx as i64 - 1, sy as i64 - 1, (sx + old_nx) as i64, (sy + old_ny) as i64);
        for y in y0..=y1 {
            for x in x0..=x1 {
                if (x == x0 || x == x1 || y == y0 || y == y1) && x >= 0 && y >= 0 && x < nx as i64 && y < ny as i64 {
                    self.changed.push((y as usize * nx + x as usize) as u32);
                }
            }
        }
        (self.nx, self.ny) = (nx, ny);
    }

    #[inline(always)]
    fn g(&self, k: usize) -> u32 {
        !self.g[k]
    }

    #[inline(always)]
    fn rhs(&self, k: usize) -> u32 {
        !self.rhs[k]
    }

    #[inline(always)]
    fn set_g(&mut self, k: usize, v: u32) {
        self.g[k] = !v;
    }

    #[inline(always)]
    fn set_rhs(&mut self, k: usize, v: u32) {
        self.rhs[k] = !v;
    }

    #[inline(always)]
    fn xy(&self, k: usize) -> (i64, i64) {
        // Grids have fewer than 2³¹ cells (see [`Queue::reset`]): a 32-bit division is cheaper.
        let (k, nx) = (k as u32, self.nx as u32);
        (i64::from(k % nx), i64::from(k / nx))
    }

    /// The key of cell `k` (infinite when no way is known): see [`Replanner::settle`].
    #[inline(always)]
    fn key(&self, k: usize) -> (u64, u64) {
        self.key_at(k, self.xy(k))
    }

    /// [`Replanner::key`] of cell `k` at `xy`.
    #[inline(always)]
    fn key_at(&self, k: usize, xy: (i64, i64)) -> (u64, u64) {
        let (g, rhs) = (self.g(k), self.rhs(k));
        let m = g.min(rhs);
        if m == INF {
            return (u64::MAX, u64::MAX);
        }
        let first = u64::from(m) + octile(self.start, xy) + self.km;
        if g < rhs { (first, u64::from(g)) } else { (first, (1 << 32) | u64::from(INF - m)) }
    }

    fn moves<'a>(&self, cells: &'a [u8]) -> Moves<'a> {
        Moves { cells, nx: self.nx as i64, ny: self.ny as i64, goal: self.goal, start: self.start, escape: self.escape }
    }

    /// The cost of the step from `(x, y)` into cell `m` (at `(mx, my)`), if a way may take it.
    #[inline(always)]
    fn edge(&self, moves: &Moves, x: i64, y: i64, step: (i64, i64, bool)) -> Option<(usize, u32)> {
        let m = moves.step(x, y, step)?;
        Some((m, self.costs[usize::from(moves.cells[m] & COST)][usize::from(step.2)]))
    }

    /// The best of cell `k`'s moves: cost plus the entered cell's `g`.
    fn best_move(&self, moves: &Moves, k: usize, (x, y): (i64, i64)) -> u32 {
        let mut best = u64::from(INF);
        if x >= 1 && y >= 1 && x + 1 < moves.nx && y + 1 < moves.ny {
            // Inside the grid's border every step stays on the grid: the moves by their offsets
            // in the cells, those onto cells with no way known first left out (the least is the
            // same whatever the order the moves are looked at in).
            let (cells, nx) = (moves.cells, moves.nx as isize);
            for &(dx, dy, diagonal) in &STEPS {
                let (dx, dy) = (dx as isize, dy as isize);
                let m = (k as isize + dy * nx + dx) as usize;
                let gm = self.g(m);
                if gm == INF
                    || !moves.enterable(m, x + dx as i64, y + dy as i64)
                    || (diagonal
                        && cells[(k as isize + dx) as usize] & cells[(k as isize + dy * nx) as usize] & HARD != 0)
                {
                    continue;
                }
                let c = self.costs[usize::from(cells[m] & COST)][usize::from(diagonal)];
                best = best.min(u64::from(c) + u64::from(gm));
            }
            return best.min(u64::from(INF)) as u32;
        }
        for &step in &STEPS {
            if let Some((m, c)) = self.edge(moves, x, y, step) {
                let gm = self.g(m);
                if gm != INF {
                    best = best.min(u64::from(c) + u64::from(gm));
                }
            }
        }
        best.min(u64::from(INF)) as u32
    }

    /// Queues cell `k` with its key when it is inconsistent and a way may enter it (or it is
    /// being settled), and takes it out of the queue otherwise.
    #[inline]
    fn queue(&mut self, moves: &Moves, k: usize, (x, y): (i64, i64)) {
        if self.g(k) != self.rhs(k) && (k == self.target || moves.enterable(k, x, y)) {
            let key = self.key_at(k, (x, y));
            self.open.set(k as u32, key);
            return;
        }
        self.open.remove(k as u32);
    }

    /// Works out cell `k` (at `xy`)'s `rhs` again and queues it if it is inconsistent.
    fn update(&mut self, moves: &Moves, k: usize, xy: (i64, i64)) {
        if k != self.goal {
            let best = self.best_move(moves, k, xy);
            self.set_rhs(k, best);
        }
        self.queue(moves, k, xy);
    }

    /// Moves the agent to cell `start`: the keys' origin moves (`km` grows by the move) and the
    /// closed cells it may cross change.
    fn move_start(&mut self, cells: &[u8], start: (i64, i64)) {
        if start == self.start {
            return;
        }
        let (old, e) = (self.start, self.escape);
        self.km += octile(old, start);
        self.start = start;
        // The cells of either square but not both may change between crossable and not.
        let inside = |c: (i64, i64), x: i64, y: i64| (x - c.0).abs().max((y - c.1).abs()) <= e;
        for &(c, other) in &[(old, start), (start, old)] {
            for y in (c.1 - e).max(0)..=(c.1 + e).min(self.ny as i64 - 1) {
                for x in (c.0 - e).max(0)..=(c.0 + e).min(self.nx as i64 - 1) {
                    let k = y as usize * self.nx + x as usize;
                    if !inside(other, x, y) && cells[k] & HARD != 0 && cells[k] & MARKED == 0 {
                        self.changed.push(k as u32);
                    }
                }
            }
        }
    }

    /// Works the changed cells into the search: the cells that may step into each, or past it
    /// diagonally, have their `rhs` worked out again.
    fn take_changes(&mut self, cells: &[u8]) {
        if self.changed.is_empty() {
            return;
        }
        let mut changed = std::mem::take(&mut self.changed);
        changed.sort_unstable();
        changed.dedup();
        let mut touched = std::mem::take(&mut self.touched);
        touched.clear();
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        for &k in &changed {
            let (x, y) = self.xy(k as usize);
            let (x0, x1, y0, y1) = ((x - 1).max(0), (x + 1).min(nx - 1), (y - 1).max(0), (y + 1).min(ny - 1));
            // Only moves into cells with a known way carry a cost: when none is known around,
            // no `rhs` changes.
            let any = (y0..=y1).any(|j| (x0..=x1).any(|i| self.g((j * nx + i) as usize) != INF));
            if !any {
                continue;
            }
            for j in y0..=y1 {
                for i in x0..=x1 {
                    touched.push((j * nx + i) as u32);
                }
            }
        }
        touched.sort_unstable();
        touched.dedup();
        let moves = self.moves(cells);
        for &k in &touched {
            self.update(&moves, k as usize, self.xy(k as usize));
        }
        self.touched = touched;
        changed.clear();
        self.changed = changed;
    }

    /// Settles cell `target` with the agent at cell `start` over `cells`, taking at most
    /// `budget` cells from the queue: its distance to the goal in cost units, or `None` when
    /// there is no way (or the budget ran out; the next call goes on from there).
    ///
    /// Keys order first by `min(g, rhs) + h + km`, as in D* Lite; among equal ones, cells whose
    /// `g` is too low (`g < rhs`) come first, by `g`, then the others by `min(g, rhs)` from the
    /// largest down — the cell nearest the agent first, so that a search over open ground
    /// follows one of the many ways of equal octile length instead of widening over all of
    /// them. The settling stops when no queued key is below the target's and the target is
    /// consistent. That is enough whatever the order: were the target's `g` too high, the last
    /// cell of a shortest way whose `g` is too high would have `rhs ≤` its distance and a key
    /// below the target's; were it too low, following the least moves from the target leads
    /// through ever lower `g` to a cell with `g < rhs` whose first key is at most the target's,
    /// and such cells come first among equals.
    pub fn settle(&mut self, cells: &[u8], start: (i64, i64), target: (i64, i64), budget: usize) -> Option<u32> {
        debug_assert!(self.ready && cells.len() == self.nx * self.ny);
        self.move_start(cells, start);
        self.take_changes(cells);
        let t = target.1 as usize * self.nx + target.0 as usize;
        self.target = t;
        let moves = self.moves(cells);
        self.update(&moves, t, target);
        let mut taken = 0usize;
        while let Some((k1, k2, k)) = self.open.first() {
            if (k1, k2) > self.key_at(t, target) && self.g(t) == self.rhs(t) {
                break;
            }
            let k = k as usize;
            let (x, y) = self.xy(k);
            let (gk, rk) = (self.g(k), self.rhs(k));
            // Keys queued before the agent moved are lower bounds: bring it up to date first.
            let now = self.key_at(k, (x, y));
            if now != (k1, k2) {
                self.open.set(k as u32, now);
                continue;
            }
            taken += 1;
            if taken > budget {
                self.expanded += taken as u64;
                return None;
            }
            self.open.remove(k as u32);
            if gk > rk {
                // A shorter way: the cells that step into this one may use it.
                self.set_g(k, rk);
                if !moves.enterable(k, x, y) {
                    continue;
                }
                let into = self.costs[usize::from(cells[k] & COST)];
                for &(dx, dy, diagonal) in &STEPS {
                    let (px, py) = (x - dx, y - dy);
                    if px < 0 || py < 0 || px >= self.nx as i64 || py >= self.ny as i64 {
                        continue;
                    }
                    if diagonal && moves.squeezed(px, py, x, y) {
                        continue;
                    }
                    let p = (py * self.nx as i64 + px) as usize;
                    let via = u64::from(into[usize::from(diagonal)]) + u64::from(rk);
                    if p != self.goal && via < u64::from(self.rhs(p)) {
                        self.set_rhs(p, via as u32);
                        self.queue(&moves, p, (px, py));
                    }
                }
            } else {
                // The way known is gone: every cell whose best move entered this one looks
                // again, and so does this one.
                self.set_g(k, INF);
                let into = self.costs[usize::from(cells[k] & COST)];
                let enterable = moves.enterable(k, x, y);
                for &(dx, dy, diagonal) in &STEPS {
                    let (px, py) = (x - dx, y - dy);
                    if px < 0 || py < 0 || px >= self.nx as i64 || py >= self.ny as i64 {
                        continue;
                    }
                    if !enterable || (diagonal && moves.squeezed(px, py, x, y)) {
                        continue;
                    }
                    let p = (py * self.nx as i64 + px) as usize;
                    if p != self.goal
                        && u64::from(self.rhs(p)) == u64::from(into[usize::from(diagonal)]) + u64::from(gk)
                    {
                        self.update(&moves, p, (px, py));
                    }
                }
                self.update(&moves, k, (x, y));
            }
        }
        self.expanded += taken as u64;
        let d = self.g(t);
        (d != INF && d == self.rhs(t)).then_some(d)
    }

    /// Cell `k`'s distance to the goal for the way down: its `g`, or where the search has not
    /// taken it from the queue, its `rhs` (the best of its moves onto cells it has).
    #[inline(always)]
    fn settled(&self, k: usize) -> u32 {
        let g = self.g(k);
        if g != INF { g } else { self.rhs(k) }
    }

    /// Cell `k`'s distance to the goal as last settled, in cost units (`u32::MAX`: none).
    pub fn distance(&self, k: usize) -> u32 {
        self.g(k)
    }

    /// The way from the settled cell `from`: up to `most` cells after it, each the move of
    /// least cost plus distance (`g`, or `rhs` for a cell the search has not taken from the
    /// queue: either is exact on a shortest way), ending early at the goal. Ways of equal cost
    /// are many on a grid (the rows of a corridor two cells wide, the orders of a way's straight
    /// and diagonal steps); among moves of equal cost the way takes a diagonal one (it turns
    /// toward where it goes early and comes straight into what lies ahead, a gap or a door,
    /// as a search from the agent does), then one going on as its last step went (`heading`,
    /// the step into `from`, for the first), then the lower index, so that it does not cross
    /// back and forth between rows of equal cost nor zigzag.
    pub fn descend(&self, cells: &[u8], from: (i64, i64), most: usize, heading: Option<(i64, i64)>) -> Vec<usize> {
        let moves = self.moves(cells);
        let mut k = from.1 as usize * self.nx + from.0 as usize;
        let mut out = vec![k];
        let mut last = heading;
        while k != self.goal && out.len() <= most {
            let (x, y) = self.xy(k);
            let mut best: Option<(u64, bool, bool, usize)> = None;
            for &step in &STEPS {
                if let Some((m, c)) = self.edge(&moves, x, y, step) {
                    let gm = self.settled(m);
                    if gm != INF {
                        let turn = last != Some((step.0, step.1));
                        let cand = (u64::from(c) + u64::from(gm), !step.2, turn, m);
                        if best.is_none_or(|b| cand < b) {
                            best = Some(cand);
                        }
                    }
                }
            }
            let Some((_, _, _, m)) = best else { break };
            if self.settled(m) >= self.settled(k) && self.settled(k) != INF {
                break; // not downhill: nothing settled further on
            }
            let (mx, my) = self.xy(m);
            last = Some((mx - x, my - y));
            k = m;
            out.push(k);
        }
        out
    }

    /// Whether a way leads from cell `start` to the goal at all over `cells`, with the agent
    /// at `start`: a plain flood, depth first with the steps toward the goal tried first,
    /// which finds a way about as fast as it is long.
    pub fn reaches(&mut self, cells: &[u8], start: (i64, i64)) -> bool {
        let n = self.nx * self.ny;
        if self.seen.len() != n {
            self.seen = vec![0; n];
            self.stamp = 0;
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.seen.iter_mut().for_each(|s| *s = 0);
            self.stamp = 1;
        }
        let stamp = self.stamp;
        let moves = Moves { start, ..self.moves(cells) };
        let nx = self.nx as i64;
        let (gx, gy) = self.xy(self.goal);
        let (gx, gy) = ((gx - start.0) as f64, (gy - start.1) as f64);
        let mut steps = STEPS;
        steps.sort_by(|a, b| (a.0 as f64 * gx + a.1 as f64 * gy).total_cmp(&(b.0 as f64 * gx + b.1 as f64 * gy)));
        let first = (start.1 * nx + start.0) as usize;
        self.seen[first] = stamp;
        let mut todo = vec![first];
        while let Some(k) = todo.pop() {
            if k == self.goal {
                return true;
            }
            let (x, y) = ((k as i64) % nx, (k as i64) / nx);
            for &step in &steps {
                if let Some(m) = moves.step(x, y, step)
                    && self.seen[m] != stamp
                {
                    self.seen[m] = stamp;
                    todo.push(m);
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;

    /// The costs the tests plan with: the memory's margin, and narrow cells dearer still.
    fn costs() -> [[u32; 2]; COST as usize + 1] {
        step_costs(4.0, 3, 40.0)
    }

    /// The from-scratch search: Dijkstra from `from` over the same moves, with the agent at
    /// `agent`.
    fn fresh(cells: &[u8], nx: usize, ny: usize, goal: usize, agent: (i64, i64), from: (i64, i64)) -> Option<u32> {
        let costs = costs();
        let moves = Moves { cells, nx: nx as i64, ny: ny as i64, goal, start: agent, escape: 2 };
        let mut dist = vec![u64::MAX; nx * ny];
        let first = from.1 as usize * nx + from.0 as usize;
        dist[first] = 0;
        let mut open = BinaryHeap::new();
        open.push(Reverse((0u64, first)));
        while let Some(Reverse((d, k))) = open.pop() {
            if d > dist[k] {
                continue;
            }
            if k == goal {
                return Some(d as u32);
            }
            let (x, y) = ((k % nx) as i64, (k / nx) as i64);
            for &step in &STEPS {
                if let Some(m) = moves.step(x, y, step) {
                    let nd = d + u64::from(costs[usize::from(cells[m] & COST)][usize::from(step.2)]);
                    if nd < dist[m] {
                        dist[m] = nd;
                        open.push(Reverse((nd, m)));
                    }
                }
            }
        }
        None
    }

    /// Marks cell `(x, y)` as the memory does (closed within one cell, the margin's bands
    /// over the next two) and tells the planner which cells changed.
    fn mark(cells: &mut [u8], nx: usize, ny: usize, at: (i64, i64), planner: &mut Replanner) {
        mark_ring(cells, nx, ny, at, false, planner);
    }

    /// [`mark`], the ring of cells around `(x, y)` [`NARROW`] instead of closed when `narrow`
    /// (as for a body with a narrower stance).
    fn mark_ring(cells: &mut [u8], nx: usize, ny: usize, (x, y): (i64, i64), narrow: bool, planner: &mut Replanner) {
        let k = y as usize * nx + x as usize;
        if cells[k] & MARKED != 0 {
            return;
        }
        cells[k] |= MARKED;
        planner.changed(k);
        for dy in -3i64..=3 {
            for dx in -3i64..=3 {
                let (i, j) = (x + dx, y + dy);
                if i < 0 || j < 0 || i >= nx as i64 || j >= ny as i64 {
                    continue;
                }
                let d = dx.abs().max(dy.abs());
                let n = j as usize * nx + i as usize;
                let was = cells[n];
                let band = (4 - d).clamp(1, 3) as u8;
                let closing = match d {
                    0 => HARD,
                    1 if narrow => NARROW,
                    1 => HARD,
                    _ => 0,
                };
                cells[n] = (was & !BAND) | (was & BAND).max(band) | closing;
                if cells[n] != was {
                    planner.changed(n);
                }
            }
        }
    }

    /// The cost of the way `descend` gives from `from`, step by step.
    fn walked(p: &Replanner, cells: &[u8], from: (i64, i64)) -> Option<u32> {
        let way = p.descend(cells, from, usize::MAX - 1, None);
        (*way.last()? == p.goal).then_some(())?;
        let moves = p.moves(cells);
        let mut total = 0u32;
        for w in way.windows(2) {
            let (x, y) = p.xy(w[0]);
            let (step, _) = STEPS
                .iter()
                .map(|&s| (s, moves.step(x, y, s)))
                .find(|&(_, m)| m == Some(w[1]))
                .expect("the way takes allowed steps");
            total += p.costs[usize::from(cells[w[1]] & COST)][usize::from(step.2)];
        }
        Some(total)
    }

    /// One change of the world the planner is told of.
    #[derive(Debug, Clone)]
    enum Op {
        /// Mark the cell at these fractions of the grid.
        Mark(f64, f64),
        /// Move the agent to these fractions of the grid.
        Move(f64, f64),
        /// Grow the grid by these many cells left, below, right and above.
        Grow(usize, usize, usize, usize),
    }

    fn op() -> impl Strategy<Value = Op> {
        prop_oneof![
            6 => (0.0..1.0f64, 0.0..1.0f64).prop_map(|(a, b)| Op::Mark(a, b)),
            2 => (0.0..1.0f64, 0.0..1.0f64).prop_map(|(a, b)| Op::Move(a, b)),
            1 => (0..4usize, 0..4usize, 0..4usize, 0..4usize).prop_map(|(a, b, c, d)| Op::Grow(a, b, c, d)),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

        /// After every change, the repaired distance of the agent's cell and of another cell
        /// equal a fresh search's, and the way followed down the distances costs as much.
        #[test]
        fn repaired_distances_equal_fresh_ones(
            nx in 4usize..24,
            ny in 4usize..24,
            goal in (0.0..1.0f64, 0.0..1.0f64),
            start in (0.0..1.0f64, 0.0..1.0f64),
            other in (0.0..1.0f64, 0.0..1.0f64),
            ops in proptest::collection::vec(op(), 1..40),
        ) {
            let at = |(a, b): (f64, f64), nx: usize, ny: usize| ((a * nx as f64) as i64, (b * ny as f64) as i64);
            let (mut nx, mut ny) = (nx, ny);
            let mut cells = vec![0u8; nx * ny];
            let mut goal = at(goal, nx, ny);
            let mut agent = at(start, nx, ny);
            let mut p = Replanner::new(costs());
            p.begin(nx, ny, goal, agent, 2);
            for op in ops {
                match op {
                    // Half the marks leave a narrow ring round their cell.
                    Op::Mark(a, b) => mark_ring(&mut cells, nx, ny, at((a, b), nx, ny), a < 0.5, &mut p),
                    Op::Move(a, b) => agent = at((a, b), nx, ny),
                    Op::Grow(l, b, r, t) => {
                        let (wx, wy) = (nx + l + r, ny + b + t);
                        let mut grown = vec![0u8; wx * wy];
                        for y in 0..ny {
                            grown[(y + b) * wx + l..(y + b) * wx + l + nx].copy_from_slice(&cells[y * nx..(y + 1) * nx]);
                        }
                        p.grow(nx, ny, wx, wy, (l, b));
                        (nx, ny, cells) = (wx, wy, grown);
                        goal = (goal.0 + l as i64, goal.1 + b as i64);
                        agent = (agent.0 + l as i64, agent.1 + b as i64);
                    }
                }
                let g = goal.1 as usize * nx + goal.0 as usize;
                let repaired = p.settle(&cells, agent, agent, usize::MAX);
                prop_assert_eq!(repaired, fresh(&cells, nx, ny, g, agent, agent));
                if repaired.is_some() {
                    prop_assert_eq!(walked(&p, &cells, agent), repaired);
                }
                let o = at(other, nx, ny);
                let repaired = p.settle(&cells, agent, o, usize::MAX);
                prop_assert_eq!(repaired, fresh(&cells, nx, ny, g, agent, o));
                if repaired.is_some() {
                    prop_assert_eq!(walked(&p, &cells, o), repaired);
                }
            }
        }
    }

    #[test]
    fn ties_keep_the_way_straight() {
        // A corridor two cells wide (rows 4 and 5) from x = 5 to x = 24 through closed cells,
        // open ground around: both rows cost the same, and the way changes rows at most once
        // (onto the row the search settled), not back and forth.
        let (nx, ny) = (30usize, 10usize);
        let mut cells = vec![0u8; nx * ny];
        for y in 0..ny {
            for x in 5..25 {
                if y != 4 && y != 5 {
                    cells[y * nx + x] = HARD;
                }
            }
        }
        let goal = (29, 4);
        let mut p = Replanner::new(costs());
        p.begin(nx, ny, goal, (2, 5), 2);
        let rows = |p: &Replanner, from: (i64, i64), heading| {
            let way = p.descend(&cells, from, usize::MAX - 1, heading);
            assert_eq!(*way.last().unwrap(), p.goal);
            way.iter().map(|&k| p.xy(k)).filter(|&(x, _)| (5..25).contains(&x)).map(|(_, y)| y).collect::<Vec<_>>()
        };
        for row in [4, 5] {
            let from = (4, row);
            let d = p.settle(&cells, from, from, usize::MAX);
            assert_eq!(d, fresh(&cells, nx, ny, p.goal, from, from));
            let rows = rows(&p, from, Some((1, 0)));
            assert!(rows.windows(2).filter(|w| w[0] != w[1]).count() <= 1, "row {row}: {rows:?}");
        }
        // In the open, the way's straight and diagonal steps come in runs: it turns at most
        // twice, not at every cell where two steps tie.
        let mut open = Replanner::new(costs());
        let cells = vec![0u8; nx * ny];
        open.begin(nx, ny, (27, 1), (1, 8), 2);
        for (from, heading) in [((1, 8), None), ((1, 8), Some((1, 0))), ((3, 2), Some((0, 1)))] {
            open.settle(&cells, from, from, usize::MAX);
            let way = open.descend(&cells, from, usize::MAX - 1, heading);
            let steps: Vec<_> = way
                .windows(2)
                .map(|w| (open.xy(w[1]).0 - open.xy(w[0]).0, open.xy(w[1]).1 - open.xy(w[0]).1))
                .collect();
            let turns = steps.windows(2).filter(|s| s[0] != s[1]).count();
            assert!(turns <= 2, "{from:?} {heading:?}: {steps:?}");
            assert_eq!(walked(&open, &cells, from), fresh(&cells, nx, ny, open.goal, from, from));
        }
    }

    #[test]
    fn repairs_cost_a_fraction_of_searches_from_scratch() {
        // An agent walks a long open grid toward the goal and sees obstacles beside its way as
        // it goes: the repairs together take far fewer cells from the queue than searching
        // afresh after each.
        let (nx, ny) = (400usize, 60usize);
        let mut cells = vec![0u8; nx * ny];
        let mut p = Replanner::new(costs());
        let goal = (390, 30);
        p.begin(nx, ny, goal, (5, 30), 2);
        let (mut repaired, mut afresh) = (0, 0);
        let mut rng = crate::rng::stream(5, 0, 0);
        for k in 0..60i64 {
            let agent = (5 + 5 * k, 30);
            for _ in 0..4 {
                let y = 30 + (crate::rng::unit(&mut rng) * 16.0) as i64 - 8;
                mark(&mut cells, nx, ny, (agent.0 + 6, y), &mut p);
            }
            let before = p.expanded;
            let d = p.settle(&cells, agent, agent, usize::MAX);
            repaired += p.expanded - before;
            let mut q = Replanner::new(costs());
            q.begin(nx, ny, goal, agent, 2);
            assert_eq!(q.settle(&cells, agent, agent, usize::MAX), d);
            afresh += q.expanded;
        }
        assert!(repaired * 4 < afresh, "repaired {repaired}, afresh {afresh}");
    }
}
