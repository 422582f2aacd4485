//! The scoped, thread-local store of series coefficients and the [`Series`] handle into it.
//!
//! A [`Series`] is 16 bytes (`Copy`, `Send`, `Sync`): a scope id, a slot number, and the constant
//! term. Its coefficients live in the arena of the [`scope`](super::scope) that made it, on the
//! thread that runs the scope; every operation appends its result as a new slot and all slots die
//! with the scope. A pure constant needs no slot and is valid everywhere. A handle met outside its
//! scope (another scope, another thread, after the scope ended) makes the result *poisoned* (no
//! coefficients, constant term NaN) and the scope records the fault, so the scope and every
//! accessor return a typed error instead of a value.

use super::monomials::Monomials;
use std::cell::RefCell;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

/// The largest number of coefficients one scope may hold, `2²⁶` (512 MiB); an operation beyond it
/// gives a poisoned value and the scope an error.
pub const MAX_ARENA_COEFFICIENTS: usize = 1 << 26;

pub(crate) const CONST: u32 = u32::MAX;
pub(crate) const POISON: u32 = u32::MAX - 1;

/// A truncated multivariate power series in `n` variables to total degree `K`,
///
/// ```math
/// s(x) = \sum_{|\alpha| \le K} s_\alpha\, x^\alpha ,\qquad x^{K+1} \equiv 0,
/// ```
///
/// as a number type: [`DualNum<f64>`](num_dual::DualNum) + `Copy` + `Send` + `Sync`, so any
/// function written once for the crate's number types evaluates on it and returns its Taylor
/// expansion to degree `K`. Values are made inside [`scope`](super::scope).
#[derive(Clone, Copy)]
pub struct Series {
    pub(crate) scope: u32,
    pub(crate) slot: u32,
    pub(crate) re: f64,
}

impl Series {
    /// The constant series `c` (valid in every scope and outside).
    pub const fn constant(c: f64) -> Self {
        Self {
            scope: 0,
            slot: CONST,
            re: c,
        }
    }

    pub(crate) const fn poison() -> Self {
        Self {
            scope: 0,
            slot: POISON,
            re: f64::NAN,
        }
    }

    /// The constant term `s₀ = s(0)`.
    pub fn constant_term(&self) -> f64 {
        self.re
    }

    /// Whether this value is a pure constant (no arena slot).
    pub fn is_constant(&self) -> bool {
        self.slot == CONST
    }

    /// Whether this value was derived from a handle used outside its scope (or from an
    /// operation the series type does not define, such as `%` of non-constants).
    pub fn is_poisoned(&self) -> bool {
        self.slot == POISON
    }
}

pub(crate) struct Arena {
    pub(crate) id: u32,
    pub(crate) table: Arc<Monomials>,
    pub(crate) data: Vec<f64>,
    pub(crate) fault: Option<String>,
    /// All zero between operations (the split-order accumulator of the truncated product).
    pub(crate) scratch: Vec<f64>,
    /// Work arrays of the elementary functions (sized on use).
    pub(crate) work: Vec<f64>,
}

/// The storage of a closed scope, kept for the next scope on the thread (no allocation when
/// scopes of similar size follow each other, e.g. one per Lie-series evaluation).
struct Buffers {
    data: Vec<f64>,
    scratch: Vec<f64>,
    work: Vec<f64>,
}

/// Buffer sets kept per thread (nested scopes take one each).
const SPARE_ENTRIES: usize = 4;
/// Buffers of larger capacity (coefficients) are freed, not kept.
const SPARE_CAPACITY: usize = 1 << 20;

thread_local! {
    static ARENA: RefCell<Option<Arena>> = const { RefCell::new(None) };
    static SPARE: RefCell<Vec<Buffers>> = const { RefCell::new(Vec::new()) };
}

static NEXT_ID: AtomicU32 = AtomicU32::new(1);

/// An operand resolved against the current arena.
pub(crate) enum Operand {
    Const(f64),
    Slot(usize),
}

impl Arena {
    fn new(table: Arc<Monomials>) -> Self {
        let mut id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
        if id == 0 {
            id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
        }
        let len = table.len();
        let Buffers {
            mut data,
            mut scratch,
            mut work,
        } = SPARE
            .try_with(|s| s.borrow_mut().pop())
            .ok()
            .flatten()
            .unwrap_or(Buffers {
                data: Vec::new(),
                scratch: Vec::new(),
                work: Vec::new(),
            });
        data.clear();
        scratch.clear();
        scratch.resize(len, 0.0);
        work.clear();
        Self {
            id,
            table,
            data,
            fault: None,
            scratch,
            work,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.table.len()
    }

    fn record(&mut self, reason: String) {
        if self.fault.is_none() {
            self.fault = Some(reason);
        }
    }

    /// The operand behind a handle, or `None` (and the fault recorded) when it does not belong
    /// here.
    pub(crate) fn resolve(&mut self, s: &Series) -> Option<Operand> {
        match s.slot {
            CONST => Some(Operand::Const(s.re)),
            POISON => {
                self.record("a poisoned series value entered an operation".into());
                None
            }
            slot if s.scope == self.id && (slot as usize + 1) * self.len() <= self.data.len() => {
                Some(Operand::Slot(slot as usize * self.len()))
            }
            _ => {
                self.record(
                    "a series value was used outside the scope that created it".to_string(),
                );
                None
            }
        }
    }

    /// Coefficients of an operand as a dense vector (copied).
    pub(crate) fn dense(&self, op: &Operand) -> Vec<f64> {
        match *op {
            Operand::Const(c) => {
                let mut v = vec![0.0; self.len()];
                v[0] = c;
                v
            }
            Operand::Slot(start) => self.data[start..start + self.len()].to_vec(),
        }
    }

    pub(crate) fn slice(&self, start: usize) -> &[f64] {
        &self.data[start..start + self.len()]
    }

    /// Store `coefficients` as a new slot.
    pub(crate) fn push(&mut self, coefficients: &[f64]) -> Series {
        let len = self.len();
        if self.data.len() + len > MAX_ARENA_COEFFICIENTS {
            self.record(format!(
                "the scope's store exceeded MAX_ARENA_COEFFICIENTS = {MAX_ARENA_COEFFICIENTS}"
            ));
            return Series::poison();
        }
        let slot = (self.data.len() / len) as u32;
        self.data.extend_from_slice(&coefficients[..len]);
        Series {
            scope: self.id,
            slot,
            re: coefficients[0],
        }
    }

    /// Store the result of `f(tables, old, out, scratch)` as a new slot, `out` zero-initialised,
    /// `old` the slots stored before, `scratch` all zero (and to be left so).
    pub(crate) fn push_with(
        &mut self,
        f: impl FnOnce(&Monomials, &[f64], &mut [f64], &mut [f64]),
    ) -> Series {
        let len = self.len();
        if self.data.len() + len > MAX_ARENA_COEFFICIENTS {
            self.record(format!(
                "the scope's store exceeded MAX_ARENA_COEFFICIENTS = {MAX_ARENA_COEFFICIENTS}"
            ));
            return Series::poison();
        }
        let start = self.data.len();
        self.data.resize(start + len, 0.0);
        let (old, new) = self.data.split_at_mut(start);
        f(&self.table, old, new, &mut self.scratch);
        Series {
            scope: self.id,
            slot: (start / len) as u32,
            re: new[0],
        }
    }
}

impl Drop for Arena {
    /// Keeps the storage for the next scope on this thread (up to `SPARE_ENTRIES` sets of at
    /// most `SPARE_CAPACITY` coefficients each).
    fn drop(&mut self) {
        let capacity = self.data.capacity() + self.scratch.capacity() + self.work.capacity();
        if capacity > SPARE_CAPACITY {
            return;
        }
        let buffers = Buffers {
            data: std::mem::take(&mut self.data),
            scratch: std::mem::take(&mut self.scratch),
            work: std::mem::take(&mut self.work),
        };
        let _ = SPARE.try_with(|s| {
            if let Ok(mut s) = s.try_borrow_mut() {
                if s.len() < SPARE_ENTRIES {
                    s.push(buffers);
                }
            }
        });
    }
}

/// Run `f` on the current thread's arena; `None` outside every scope.
pub(crate) fn with_arena<R>(f: impl FnOnce(&mut Arena) -> R) -> Option<R> {
    ARENA.with(|a| a.borrow_mut().as_mut().map(f))
}

/// Restores the enclosing scope's arena on drop (also on unwinding).
struct Restore(Option<Option<Arena>>);

impl Drop for Restore {
    fn drop(&mut self) {
        if let Some(previous) = self.0.take() {
            ARENA.with(|a| *a.borrow_mut() = previous);
        }
    }
}

/// Open an arena for `table` on this thread, run `f(id)`, close it; returns `f`'s value and the
/// first fault recorded.
pub(crate) fn in_arena<R>(table: Arc<Monomials>, f: impl FnOnce(u32) -> R) -> (R, Option<String>) {
    let arena = Arena::new(table);
    let id = arena.id;
    let previous = ARENA.with(|a| a.borrow_mut().replace(arena));
    let guard = Restore(Some(previous));
    let r = f(id);
    let fault = ARENA.with(|a| a.borrow().as_ref().and_then(|a| a.fault.clone()));
    drop(guard);
    (r, fault)
}
