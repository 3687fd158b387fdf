//! Where a run's numbers go: one column per [`Quantity`] (body-major: each body's output
//! times, each time's numbers), the principal moments and the cost per body; each body's
//! share of them as safe, disjoint slices, handed out a window of bodies at a time; and the
//! writer of one body's samples into its share.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use rayon::iter::plumbing::{bridge, Consumer, Producer, ProducerCallback, UnindexedConsumer};
use rayon::prelude::*;

use super::job::Job;
use super::quantity::{write_row, Quantity, Sample};
use crate::dynamics::{Gyrostat, Stats};
use crate::memory::{self, Purpose};
use crate::{Error, Result};

/// The outputs of [`super::simulate`]: for each [`Quantity`] present, N x M x width numbers,
/// body-major, then the principal moments (N x 3) and the cost per body.
#[derive(Clone, Debug, PartialEq)]
pub struct Outputs {
    /// Bodies.
    pub n: usize,
    /// Output times.
    pub m: usize,
    /// Rotors (the widths of [`Quantity::ROTOR_RATES`]).
    pub rotors: usize,
    /// The quantities present (those needing the orientation only with it, those needing
    /// rotors only with them), in the order of [`Quantity::ALL`], and their numbers.
    pub columns: Vec<(Quantity, Vec<f64>)>,
    /// The principal moments each body was integrated with (about the pivot for a heavy top),
    /// N x 3, ascending for a body given by a tensor or mass properties.
    pub moments: Vec<f64>,
    /// What each body cost.
    pub stats: Vec<Stats>,
}

impl Outputs {
    /// The numbers of the quantity named `name`, if present.
    #[must_use]
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|(q, _)| q.name() == name)
            .map(|(_, data)| data.as_slice())
    }

    /// Zeroed outputs of `n` bodies for the quantities of `layout`, or
    /// [`Error::OutOfMemory`] if they cannot be allocated.
    pub(crate) fn zeroed(n: usize, layout: &Layout) -> Result<Self> {
        let m = layout.t.len();
        let per_time: usize = layout.widths().iter().sum();
        // The error gives the size of all the outputs (a product that may exceed usize).
        let bytes = (n as f64) * (m as f64) * (per_time as f64) * 8.0;
        let all = |_| Purpose::Outputs.error(bytes);
        let size = |width: usize| {
            n.checked_mul(m)
                .and_then(|nm| nm.checked_mul(width))
                .ok_or_else(|| Purpose::Outputs.error(bytes))
        };
        let mut columns = memory::with_capacity(layout.count, Purpose::Outputs)?;
        for (quantity, width) in layout.quantities().zip(layout.widths()) {
            columns.push((
                *quantity,
                memory::zeros(size(width)?, Purpose::Outputs).map_err(all)?,
            ));
        }
        Ok(Self {
            n,
            m,
            rotors: layout.rotors,
            columns,
            moments: memory::zeros(3 * n, Purpose::Outputs).map_err(all)?,
            stats: memory::filled(n, Stats::default(), Purpose::Outputs).map_err(all)?,
        })
    }

    /// Every body's share of the outputs.
    pub(crate) fn share(&mut self) -> Share<'_> {
        let (m, rotors) = (self.m, self.rotors);
        let mut columns: [&mut [f64]; COLUMNS] = Default::default();
        let mut widths = [0; COLUMNS];
        for (c, (quantity, data)) in self.columns.iter_mut().enumerate().take(COLUMNS) {
            widths[c] = m * quantity.width(rotors);
            columns[c] = data;
        }
        Share {
            first: 0,
            count: self.n,
            columns,
            widths,
            moments: &mut self.moments,
            stats: &mut self.stats,
        }
    }
}

/// The most columns a run has.
pub(crate) const COLUMNS: usize = Quantity::ALL.len();

/// Consecutive bodies' shares of the outputs (bodies `first..first + count`): their rows of
/// each column (in the order of [`Outputs::columns`]), their principal moments and their
/// costs. Split, never copied: each body's share is a disjoint part of the outputs.
pub(crate) struct Share<'a> {
    pub(crate) first: usize,
    pub(crate) count: usize,
    columns: [&'a mut [f64]; COLUMNS],
    /// Each column's numbers per body.
    widths: [usize; COLUMNS],
    moments: &'a mut [f64],
    stats: &'a mut [Stats],
}

impl<'a> Share<'a> {
    /// The first `k` bodies' shares, and the rest.
    pub(crate) fn split_at(self, k: usize) -> (Self, Self) {
        let k = k.min(self.count);
        let mut head: [&'a mut [f64]; COLUMNS] = Default::default();
        let mut tail: [&'a mut [f64]; COLUMNS] = Default::default();
        for (c, column) in self.columns.into_iter().enumerate() {
            (head[c], tail[c]) = column.split_at_mut(k * self.widths[c]);
        }
        let (moments, rest_moments) = self.moments.split_at_mut(3 * k);
        let (stats, rest_stats) = self.stats.split_at_mut(k);
        (
            Share {
                first: self.first,
                count: k,
                columns: head,
                widths: self.widths,
                moments,
                stats,
            },
            Share {
                first: self.first + k,
                count: self.count - k,
                columns: tail,
                widths: self.widths,
                moments: rest_moments,
                stats: rest_stats,
            },
        )
    }

    /// Each body's share, in order.
    pub(crate) fn bodies(self) -> impl Iterator<Item = BodyRows<'a>> {
        let mut rest = self;
        std::iter::from_fn(move || {
            if rest.count == 0 {
                return None;
            }
            let (head, tail) = std::mem::replace(&mut rest, Share::empty()).split_at(1);
            rest = tail;
            Some(BodyRows {
                index: head.first,
                columns: head.columns,
                moments: head.moments,
                stats: head.stats,
            })
        })
    }

    fn empty() -> Self {
        Share {
            first: 0,
            count: 0,
            columns: Default::default(),
            widths: [0; COLUMNS],
            moments: &mut [],
            stats: &mut [],
        }
    }

    /// `f(rows)` for each window of at most `window` consecutive bodies, `rows` their shares
    /// in order; `f`'s error stops the walk and is returned.
    pub(crate) fn by_window<E>(
        self,
        window: usize,
        mut f: impl FnMut(&mut [BodyRows<'a>]) -> std::result::Result<(), E>,
    ) -> std::result::Result<(), E> {
        let mut rows: Vec<BodyRows<'a>> = Vec::with_capacity(window.min(self.count));
        let mut rest = self;
        while rest.count > 0 {
            let (head, tail) = rest.split_at(window.max(1));
            rest = tail;
            rows.clear();
            rows.extend(head.bodies());
            f(&mut rows)?;
        }
        Ok(())
    }
}

impl<'a> Share<'a> {
    /// Its blocks of `size` consecutive bodies (the last one shorter), as a parallel iterator
    /// that rayon splits at block boundaries, without making a list of them.
    pub(crate) fn blocks(self, size: usize) -> Blocks<'a> {
        Blocks {
            share: self,
            size: size.max(1),
        }
    }
}

/// The blocks of a [`Share`] (see [`Share::blocks`]): an indexed parallel iterator, its own
/// producer.
pub(crate) struct Blocks<'a> {
    share: Share<'a>,
    size: usize,
}

impl<'a> ParallelIterator for Blocks<'a> {
    type Item = Share<'a>;

    fn drive_unindexed<C: UnindexedConsumer<Self::Item>>(self, consumer: C) -> C::Result {
        bridge(self, consumer)
    }

    fn opt_len(&self) -> Option<usize> {
        Some(self.len())
    }
}

impl IndexedParallelIterator for Blocks<'_> {
    fn len(&self) -> usize {
        self.share.count.div_ceil(self.size)
    }

    fn drive<C: Consumer<Self::Item>>(self, consumer: C) -> C::Result {
        bridge(self, consumer)
    }

    fn with_producer<CB: ProducerCallback<Self::Item>>(self, callback: CB) -> CB::Output {
        callback.callback(BlockProducer {
            share: self.share,
            size: self.size,
        })
    }
}

/// The producer of [`Blocks`], and its sequential iterator.
struct BlockProducer<'a> {
    share: Share<'a>,
    size: usize,
}

impl<'a> Producer for BlockProducer<'a> {
    type Item = Share<'a>;
    type IntoIter = Self;

    fn into_iter(self) -> Self {
        self
    }

    fn split_at(self, index: usize) -> (Self, Self) {
        let (head, tail) = self.share.split_at(index * self.size);
        let size = self.size;
        (
            BlockProducer { share: head, size },
            BlockProducer { share: tail, size },
        )
    }
}

impl<'a> Iterator for BlockProducer<'a> {
    type Item = Share<'a>;

    fn next(&mut self) -> Option<Share<'a>> {
        if self.share.count == 0 {
            return None;
        }
        let rest = std::mem::replace(&mut self.share, Share::empty());
        let (block, tail) = rest.split_at(self.size);
        self.share = tail;
        Some(block)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.share.count.div_ceil(self.size);
        (n, Some(n))
    }
}

impl DoubleEndedIterator for BlockProducer<'_> {
    fn next_back(&mut self) -> Option<Self::Item> {
        let n = self.share.count.div_ceil(self.size);
        if n == 0 {
            return None;
        }
        let rest = std::mem::replace(&mut self.share, Share::empty());
        let (head, last) = rest.split_at((n - 1) * self.size);
        self.share = head;
        Some(last)
    }
}

impl ExactSizeIterator for BlockProducer<'_> {}

/// One body's share of the outputs: its index, its rows of each column (in the order of
/// [`Outputs::columns`]; the entries past them empty), its principal moments (3 numbers) and
/// its cost (1); all empty once taken.
#[derive(Default)]
pub(crate) struct BodyRows<'a> {
    pub(crate) index: usize,
    pub(crate) columns: [&'a mut [f64]; COLUMNS],
    pub(crate) moments: &'a mut [f64],
    pub(crate) stats: &'a mut [Stats],
}

/// What a run reports at each output time: its quantities (the columns: the first `count` of
/// `columns`, each with its numbers per output time), whether it has the orientation, its
/// number of rotors, and the output times.
pub(crate) struct Layout<'t> {
    columns: [(Quantity, usize); COLUMNS],
    count: usize,
    pub(crate) with_orientation: bool,
    pub(crate) rotors: usize,
    pub(crate) t: &'t [f64],
}

impl<'t> Layout<'t> {
    /// The quantities of a run with or without the orientation and with `rotors` rotors, at
    /// the output times `t`.
    pub(crate) fn new(with_orientation: bool, rotors: usize, t: &'t [f64]) -> Self {
        let mut columns = [(Quantity::OMEGA, 0); COLUMNS];
        let mut count = 0;
        for quantity in Quantity::ALL {
            if (with_orientation || !quantity.needs_orientation())
                && (rotors > 0 || !quantity.needs_rotors())
            {
                columns[count] = (quantity, quantity.width(rotors));
                count += 1;
            }
        }
        Self {
            columns,
            count,
            with_orientation,
            rotors,
            t,
        }
    }

    /// The quantities, in the order of the columns.
    pub(crate) fn quantities(&self) -> impl Iterator<Item = &Quantity> {
        self.columns[..self.count].iter().map(|(q, _)| q)
    }

    /// Each column's numbers per output time.
    pub(crate) fn widths(&self) -> [usize; COLUMNS] {
        self.columns.map(|(_, w)| w)
    }

    /// The position of `quantity` among the columns, if present.
    pub(crate) fn position(&self, quantity: Quantity) -> Option<usize> {
        self.quantities().position(|q| *q == quantity)
    }
}

/// Writes one body's samples into its rows (or into a chunk of its output times, from
/// `layout.t[first]`): every quantity of the layout at each output time, then checks them
/// finite.
pub(crate) struct Writer<'w, 'a> {
    layout: &'w Layout<'w>,
    columns: [&'a mut [f64]; COLUMNS],
    /// The index of the first output time of the rows.
    first: usize,
    /// The last quaternion written, if the writer keeps its sign continuous (one sign per
    /// trajectory); `None` when the signs are settled afterwards.
    previous: Option<Option<Quaternion<f64>>>,
    /// The first output that is not finite: the body's error, unless its run fails.
    failed: Option<Error>,
}

impl<'w, 'a> Writer<'w, 'a> {
    /// A writer of `columns` from output time `first`, keeping the quaternions' signs
    /// continuous if `continuous`.
    pub(crate) fn new(
        layout: &'w Layout<'w>,
        columns: [&'a mut [f64]; COLUMNS],
        first: usize,
        continuous: bool,
    ) -> Self {
        Self {
            layout,
            columns,
            first,
            previous: continuous.then_some(None),
            failed: None,
        }
    }

    /// Writes the sample of `job` at output time `j` (an index of `layout.t`): its angular
    /// velocity and orientation in principal axes, and its rotors' variables if any. An
    /// output that is not finite is kept as the body's error ([`Writer::finish`]); nothing is
    /// written after it.
    #[inline(always)]
    pub(crate) fn write(
        &mut self,
        j: usize,
        job: &Job,
        omega: &Vector3<f64>,
        orientation: Option<&UnitQuaternion<f64>>,
        rotors: Option<(&Gyrostat, &[f64])>,
    ) {
        if self.failed.is_some() {
            return;
        }
        let sample = Sample::new(job, omega, orientation, rotors, self.previous.as_mut());
        let row = j - self.first;
        let columns = &mut self.columns;
        let probe = match (self.layout.with_orientation, self.layout.rotors) {
            (false, 0) => write_row::<false, false>(&sample, columns, row, 0),
            (true, 0) => write_row::<true, false>(&sample, columns, row, 0),
            (false, k) => write_row::<false, true>(&sample, columns, row, k),
            (true, k) => write_row::<true, true>(&sample, columns, row, k),
        };
        // Every number is written, then checked finite at once: their sum is finite unless
        // one is not (or the sum overflows); the rows are looked through only then.
        if !probe.is_finite() {
            self.failed = self.not_finite(j, row);
        }
    }

    /// The error of the first number of output time `j` (row `row`) that is not finite.
    #[cold]
    fn not_finite(&self, j: usize, row: usize) -> Option<Error> {
        let widths = self.layout.widths();
        for (c, quantity) in self.layout.quantities().enumerate() {
            let w = widths[c];
            // omega is finite (the integration checks it), but I omega and T can overflow
            // beside it (a torque that drives the motion beyond doubles).
            if let Some(&value) = self.columns[c][row * w..(row + 1) * w]
                .iter()
                .find(|x| !x.is_finite())
            {
                return Some(Error::BlewUp {
                    name: "t".into(),
                    what: format!("`{}`", quantity.name()),
                    hint: "the motion leaves double precision before the times asked for.".into(),
                    t: self.layout.t[j],
                    value,
                });
            }
        }
        None
    }

    /// The body's result: the run's (`ran`), or if it succeeded, the error of its first
    /// output that is not finite.
    pub(crate) fn finish(self, ran: Result<Stats>) -> Result<Stats> {
        let stats = ran?;
        match self.failed {
            Some(error) => Err(error),
            None => Ok(stats),
        }
    }

    /// The error of the first output that is not finite, if any.
    pub(crate) fn failed(&mut self) -> Option<Error> {
        self.failed.take()
    }
}
