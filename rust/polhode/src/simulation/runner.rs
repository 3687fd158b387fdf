//! The one runner: each body a prepared [`Job`], run by the equations of the run (a rigid
//! body, a body with rotors: [`Equations`]) with one of three strategies:
//!
//! - **scalar**: one body at a time through the dynamics' loops, its outputs written as they
//!   come ([`Equations::run`]);
//! - **exact**: the closed form of a torque-free rigid body, its output times evaluated in
//!   chunks (on the rayon pool for more than one), the quaternions' signs settled afterwards;
//! - **lanes**: blocks of up to [`lanes::LANES`] torque-free rigid bodies integrated together
//!   in SIMD lanes by a fixed-step method.
//!
//! Every body is run on its own numbers: a body's outputs are the same bit for bit alone or in
//! a batch, by any strategy that applies to it, whatever the number of threads.

use std::cell::RefCell;

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use rayon::prelude::*;

use super::job::{axis_order, Job};
use super::output::{BodyRows, Layout, Outputs, Share, Writer, COLUMNS};
use super::quantity::Quantity;
use super::{Body, Simulation};
use crate::dynamics::lanes::{self, LaneOutputs};
use crate::dynamics::{
    exact_range, omega_scale, run_body, run_body_with_steps, run_gyrostat, run_gyrostat_with_steps,
    start, start_state, Gyrostat, Method, Options, RotorSpec, State, Stats, Torque,
};
use crate::exact::FreeRotation;
use crate::memory::{self, Purpose};
use crate::monitor::{running, Failures};
use crate::{Error, Monitor, Result};
use std::sync::Arc;

/// Outputs written between two looks at the monitor (a few hundred microseconds).
const OUTPUT_LOOK_EVERY: usize = 4096;

/// Output times of one body evaluated together by the exact solution: the unit of its work
/// on the rayon pool (about a millisecond).
pub(crate) const EXACT_CHUNK: usize = 4096;

/// Bodies grouped together by the splitting's axis order into lane blocks (see
/// [`Share::by_window`]): a few megabytes of slices.
const WINDOW: usize = 16_384;

/// A run of N bodies: its settings, the bodies as given and what each body's job is made of.
pub(crate) struct Context<'c> {
    pub(crate) run: &'c Simulation,
    pub(crate) bodies: &'c [Body],
    pub(crate) omega0: &'c [Vector3<f64>],
    pub(crate) orientation0: &'c [UnitQuaternion<f64>],
    pub(crate) layout: Layout<'c>,
    pub(crate) monitor: Option<&'c Monitor>,
    /// The batch's first failure: the bodies after it stop (see [`Failures`]).
    pub(crate) failures: Arc<Failures>,
}

impl Context<'_> {
    /// Body `i`'s job (a body or orientation given once is shared by all).
    fn job(&self, i: usize) -> Result<Job> {
        let at = |len: usize| if len == 1 { 0 } else { i };
        Job::new(
            &self.bodies[at(self.bodies.len())],
            self.run.torque.as_ref(),
            &self.omega0[i],
            &self.orientation0[at(self.orientation0.len())],
        )
    }

    /// The options of a body's run under its `torque` (principal axes).
    fn options<'o>(&'o self, torque: Option<&'o (dyn Torque + Send)>) -> Options<'o> {
        Options {
            t0: self.run.t0,
            with_orientation: self.run.with_orientation,
            torque: torque.map(|t| t as &dyn Torque),
            max_steps: self.run.max_steps,
            monitor: self.monitor,
        }
    }

    /// Body `i` failed with `error`: the bodies after it stop (see [`Failures`]).
    fn failed(&self, i: usize, error: Error) -> (usize, Error) {
        self.failures.fail(i);
        (i, error)
    }

    /// A look at the monitor every [`OUTPUT_LOOK_EVERY`] outputs: writing millions of them
    /// takes a while.
    #[inline]
    fn look(&self, j: usize) -> Result<()> {
        if j % OUTPUT_LOOK_EVERY == OUTPUT_LOOK_EVERY - 1 {
            if let Some(monitor) = self.monitor {
                monitor.look()?;
            }
        }
        Ok(())
    }
}

/// The equations a run integrates, each body by the scalar strategy (or one of its own).
pub(crate) trait Equations: Sync {
    /// Runs `job` to the output times, writing its samples through `writer`.
    fn run(&self, ctx: &Context, job: &Job, writer: &mut Writer) -> Result<Stats>;

    /// Runs body `i`'s `job` into `columns` (its rows): by default the scalar strategy.
    fn run_body(&self, ctx: &Context, job: &Job, columns: [&mut [f64]; COLUMNS]) -> Result<Stats> {
        let mut writer = Writer::new(&ctx.layout, columns, 0, true);
        let ran = self.run(ctx, job, &mut writer);
        writer.finish(ran)
    }

    /// Whether the bodies run in blocks of SIMD lanes (see [`block_of_lanes`]).
    fn in_lanes(&self, ctx: &Context) -> bool {
        let _ = ctx;
        false
    }

    /// Runs `job` by `dop853` to the last output time, reporting its states at the output
    /// times and at the end of every accepted step (see [`every_step`]).
    fn every_step(&self, ctx: &Context, job: &Job) -> Result<(Vec<f64>, Outputs)>;
}

/// One body's states in time order, in its principal axes (with its rotors' variables,
/// `stride` numbers each): the samples of the every-step strategy, written afterwards.
#[derive(Default)]
pub(crate) struct Samples {
    t: Vec<f64>,
    omega: Vec<Vector3<f64>>,
    orientation: Vec<Option<UnitQuaternion<f64>>>,
    vars: Vec<f64>,
}

impl Samples {
    /// The state at `t`, unless it is at or before the last one's time (a step that ends at
    /// an output time is reported once). The samples grow with the run's steps, which the
    /// input does not bound: through `memory`, an [`Error::OutOfMemory`] rather than an abort.
    fn push(
        &mut self,
        t: f64,
        w: &Vector3<f64>,
        q: Option<&UnitQuaternion<f64>>,
        vars: &[f64],
    ) -> Result<()> {
        if self.t.last().is_some_and(|&last| t <= last) {
            return Ok(());
        }
        memory::push(&mut self.t, t, Purpose::Outputs)?;
        memory::push(&mut self.omega, *w, Purpose::Outputs)?;
        memory::push(&mut self.orientation, q.copied(), Purpose::Outputs)?;
        memory::extend(&mut self.vars, vars, Purpose::Outputs)
    }

    /// Outputs of one body at the samples' times, written from them (the quaternions' signs
    /// continuous in time), the body's moments and `stats`; and those times.
    fn write(
        self,
        ctx: &Context,
        job: &Job,
        gyrostat: Option<&Gyrostat>,
        stats: Stats,
    ) -> Result<(Vec<f64>, Outputs)> {
        let layout = Layout::new(ctx.layout.with_orientation, ctx.layout.rotors, &self.t);
        let mut outputs = Outputs::zeroed(1, &layout)?;
        let share = outputs.share();
        let rows = share.bodies().next().expect("one body");
        rows.moments
            .copy_from_slice(job.moments.moments().as_slice());
        let mut writer = Writer::new(&layout, rows.columns, 0, true);
        let stride = gyrostat.map_or(0, Gyrostat::variables);
        for (j, (w, q)) in self.omega.iter().zip(&self.orientation).enumerate() {
            ctx.look(j)?;
            let vars = &self.vars[j * stride..(j + 1) * stride];
            writer.write(j, job, w, q.as_ref(), gyrostat.map(|g| (g, vars)));
        }
        rows.stats[0] = writer.finish(Ok(stats))?;
        Ok((self.t, outputs))
    }
}

/// The every-step strategy: one body by `dop853`, its states at the output times and at the
/// end of every accepted step, in time order, collected as they come and then written.
pub(crate) fn every_step<E: Equations>(
    equations: &E,
    ctx: &Context,
) -> Result<(Vec<f64>, Outputs)> {
    let job = ctx.job(0)?;
    equations.every_step(ctx, &job)
}

/// Euler's equations of a rigid body: the scalar strategy through the driver's loops, the
/// exact strategy for [`Method::Exact`], and lanes for a torque-free batch by a fixed-step
/// method.
pub(crate) struct RigidBody;

impl Equations for RigidBody {
    fn run(&self, ctx: &Context, job: &Job, writer: &mut Writer) -> Result<Stats> {
        let options = ctx.options(job.torque.as_deref());
        run_body(
            &ctx.run.method,
            &job.moments,
            &job.state,
            ctx.layout.t,
            &options,
            &mut |j, w, q| {
                ctx.look(j)?;
                writer.write(j, job, w, q, None);
                Ok(())
            },
        )
    }

    fn run_body(&self, ctx: &Context, job: &Job, columns: [&mut [f64]; COLUMNS]) -> Result<Stats> {
        if matches!(ctx.run.method, Method::Exact) {
            return exact(ctx, job, columns);
        }
        let mut writer = Writer::new(&ctx.layout, columns, 0, true);
        let ran = self.run(ctx, job, &mut writer);
        writer.finish(ran)
    }

    fn every_step(&self, ctx: &Context, job: &Job) -> Result<(Vec<f64>, Outputs)> {
        let options = ctx.options(job.torque.as_deref());
        let t = ctx.layout.t;
        let samples = RefCell::new(Samples::default());
        let stats = run_body_with_steps(
            &ctx.run.method,
            &job.moments,
            &job.state,
            t,
            &options,
            &mut |j, w, q| {
                ctx.look(j)?;
                samples.borrow_mut().push(t[j], w, q, &[])
            },
            Some(&mut |time, w, q| samples.borrow_mut().push(time, w, q, &[])),
        )?;
        samples.into_inner().write(ctx, job, None, stats)
    }

    fn in_lanes(&self, ctx: &Context) -> bool {
        let options = ctx.options(None);
        ctx.omega0.len() > 1
            && ctx.run.torque.is_none()
            && lanes::applies(&ctx.run.method, &options)
    }
}

/// The gyrostat equations of a body with internal rotors (shared by every body), by the
/// scalar strategy.
pub(crate) struct WithRotors<'r> {
    pub(crate) rotors: &'r [RotorSpec],
}

impl Equations for WithRotors<'_> {
    fn run(&self, ctx: &Context, job: &Job, writer: &mut Writer) -> Result<Stats> {
        let gyrostat = Gyrostat::new(job.moments.moments(), &job.axes(), self.rotors)?;
        let options = ctx.options(job.torque.as_deref());
        run_gyrostat(
            &ctx.run.method,
            &gyrostat,
            &job.state,
            ctx.layout.t,
            &options,
            &mut |j, w, q, vars| {
                ctx.look(j)?;
                writer.write(j, job, w, Some(q), Some((&gyrostat, vars)));
                Ok(())
            },
        )
    }

    fn every_step(&self, ctx: &Context, job: &Job) -> Result<(Vec<f64>, Outputs)> {
        let gyrostat = Gyrostat::new(job.moments.moments(), &job.axes(), self.rotors)?;
        let options = ctx.options(job.torque.as_deref());
        let t = ctx.layout.t;
        let samples = RefCell::new(Samples::default());
        let stats = run_gyrostat_with_steps(
            &ctx.run.method,
            &gyrostat,
            &job.state,
            t,
            &options,
            &mut |j, w, q, vars| {
                ctx.look(j)?;
                samples.borrow_mut().push(t[j], w, Some(q), vars)
            },
            Some(&mut |time, w, q, vars| samples.borrow_mut().push(time, w, Some(q), vars)),
        )?;
        samples.into_inner().write(ctx, job, Some(&gyrostat), stats)
    }
}

/// Runs every body of `ctx` by `equations` into `outputs`; the error of the first failing
/// body by index, wrapped in [`Error::Body`] when there is more than one body.
pub(crate) fn run<E: Equations>(equations: &E, ctx: &Context, outputs: &mut Outputs) -> Result<()> {
    let n = ctx.omega0.len();
    let share = outputs.share();
    let failed = if !equations.in_lanes(ctx) {
        on_blocks(ctx, share, 1, |block| {
            block.bodies().find_map(|body| {
                let i = body.index;
                let ran = ctx.failures.run_as(i, || one(equations, ctx, body));
                ran.err().map(|e| ctx.failed(i, e))
            })
        })
    } else if matches!(ctx.run.method, Method::Splitting { .. }) && ctx.bodies.len() > 1 {
        // The splitting's blocks share an axis order: grouped a window at a time.
        share
            .by_window(WINDOW, |rows| {
                let mut blocks = grouped_blocks(ctx, rows);
                let parallel = ctx.run.parallel && blocks.len() > 1;
                first_error(parallel, &mut blocks, |block| {
                    // Rows in ascending order of index within a block.
                    let first = block.first().map_or(0, |rows| rows.index);
                    if ctx.failures.stops(first) {
                        return None;
                    }
                    ctx.failures.run_as(first, || {
                        block_of_lanes(equations, ctx, block.iter_mut().map(std::mem::take))
                    })
                })
                .map_or(Ok(()), Err)
            })
            .err()
    } else {
        on_blocks(ctx, share, lanes::LANES, |block| {
            ctx.failures.run_as(block.first, || {
                block_of_lanes(equations, ctx, block.bodies())
            })
        })
    };
    match failed {
        None => Ok(()),
        Some((i, error)) if n > 1 => Err(error.in_body(i)),
        Some((_, error)) => Err(error),
    }
}

/// `f` on each block of `size` consecutive bodies of `share` (the last one shorter), on the
/// rayon pool if the run is parallel (an indexed parallel iterator of the blocks, split as the
/// pool asks; [`rayon::iter::split`]'s halving, unindexed, ran 12% slower on a batch started
/// from a thread of the pool, as the binding starts it): the first error by body index.
fn on_blocks<'a>(
    ctx: &Context,
    share: Share<'a>,
    size: usize,
    f: impl Fn(Share<'a>) -> Option<(usize, Error)> + Sync,
) -> Option<(usize, Error)> {
    // A block after the batch's first failure is skipped: it cannot hold the first error.
    let f = |block: Share<'a>| {
        if ctx.failures.stops(block.first) {
            None
        } else {
            f(block)
        }
    };
    let in_order = |share: Share<'a>| {
        let mut rest = share;
        let mut failed = None;
        while rest.count > 0 {
            let (block, tail) = rest.split_at(size);
            rest = tail;
            // The blocks come in order: the first error is the first block's.
            failed = failed.or_else(|| f(block));
        }
        failed
    };
    if !ctx.run.parallel || share.count <= size {
        return in_order(share);
    }
    share.blocks(size).filter_map(&f).min_by_key(|(i, _)| *i)
}

/// `f` on each of `items`, on the rayon pool if `parallel`: the first error by body index.
fn first_error<T: Send>(
    parallel: bool,
    items: &mut [T],
    f: impl Fn(&mut T) -> Option<(usize, Error)> + Sync,
) -> Option<(usize, Error)> {
    if parallel {
        items.par_iter_mut().filter_map(&f).min_by_key(|(i, _)| *i)
    } else {
        items.iter_mut().filter_map(f).min_by_key(|(i, _)| *i)
    }
}

/// A body: its job, then its run by its strategy into its rows.
fn one<E: Equations>(equations: &E, ctx: &Context, rows: BodyRows) -> Result<()> {
    let job = ctx.job(rows.index)?;
    rows.moments
        .copy_from_slice(job.moments.moments().as_slice());
    rows.stats[0] = equations.run_body(ctx, &job, rows.columns)?;
    Ok(())
}

/// The exact strategy: a torque-free rigid body by its closed form, its outputs at the times
/// written straight into its rows as they are evaluated, in chunks of [`EXACT_CHUNK`] times
/// (on the rayon pool if the run is parallel and there is more than one). The quaternions
/// are made continuous in time afterwards, in one pass in order (looking at the monitor as
/// the writing of outputs does): the same signs as written one time after another. The
/// numbers do not depend on the chunks nor on the threads. The error is that of the first
/// time whose evaluation fails (a cancelled monitor, a time beyond the solution's reach), else
/// of the first output that is not finite, as when the whole trajectory is evaluated before
/// it is written.
fn exact(ctx: &Context, job: &Job, mut columns: [&mut [f64]; COLUMNS]) -> Result<Stats> {
    let t = ctx.layout.t;
    let options = ctx.options(None);
    let state0 = start(&Method::Exact, &job.state, t, &options)?;
    let free = FreeRotation::new(*job.moments.moments(), state0.omega, state0.orientation)?;
    let layout = &ctx.layout;
    let widths = layout.widths();
    // One chunk: the first error of an evaluation, or else of an output.
    let chunk = |(start, rows): (usize, [&mut [f64]; COLUMNS])| -> (Option<Error>, Option<Error>) {
        let count = EXACT_CHUNK.min(t.len() - start);
        let mut writer = Writer::new(layout, rows, start, false);
        let evaluated = exact_range(&free, t, start..start + count, &options, |j, w, q| {
            writer.write(j, job, w, q, None);
            Ok(())
        });
        (evaluated.err(), writer.failed())
    };
    let results: Vec<(Option<Error>, Option<Error>)> = if t.len() <= EXACT_CHUNK {
        vec![chunk((0, columns.each_mut().map(|c| &mut **c)))]
    } else {
        // Each chunk's rows of each column.
        let mut chunks: Vec<(usize, [&mut [f64]; COLUMNS])> = (0..t.len())
            .step_by(EXACT_CHUNK)
            .map(|start| (start, Default::default()))
            .collect();
        for (c, column) in columns.iter_mut().enumerate() {
            let rows = column.chunks_mut(EXACT_CHUNK * widths[c].max(1));
            for ((_, chunk), rows) in chunks.iter_mut().zip(rows) {
                chunk[c] = rows;
            }
        }
        if ctx.run.parallel {
            // Each chunk as the body whose chunk it is, on whichever thread runs it.
            let body = running();
            chunks
                .into_par_iter()
                .map(|c| match &body {
                    Some((failures, i)) => failures.run_as(*i, || chunk(c)),
                    None => chunk(c),
                })
                .collect()
        } else {
            chunks.into_iter().map(chunk).collect()
        }
    };
    let mut output_error = None;
    for (evaluation, output) in results {
        if let Some(error) = evaluation {
            return Err(error);
        }
        output_error = output_error.or(output);
    }
    if let Some(error) = output_error {
        return Err(error);
    }
    // The run is done; its outputs are settled as written ones are, looking at the monitor.
    if let Some(monitor) = options.monitor {
        monitor.add_finished();
    }
    if let Some(c) = layout.position(Quantity::QUATERNION) {
        continuous_signs(ctx, columns[c])?;
    }
    Ok(Stats {
        steps: 0,
        rejected_steps: 0,
        rhs_evaluations: t.len() as u64,
    })
}

/// Makes the quaternions `(x, y, z, w)` of `rows` continuous in time: one sign per
/// trajectory, as [`Writer`] keeps it when it writes them in order.
fn continuous_signs(ctx: &Context, rows: &mut [f64]) -> Result<()> {
    let mut previous: Option<Quaternion<f64>> = None;
    for (j, row) in rows.chunks_exact_mut(4).enumerate() {
        ctx.look(j)?;
        let mut q = Quaternion::new(row[3], row[0], row[1], row[2]);
        if previous.is_some_and(|p| p.coords.dot(&q.coords) < 0.0) {
            q = -q;
            row.copy_from_slice(&[q.i, q.j, q.k, q.w]);
        }
        previous = Some(q);
    }
    Ok(())
}

/// The blocks of at most [`lanes::LANES`] bodies of a window integrated together by the
/// splitting, whose bodies are grouped by their axis order (`None` for a body that fails
/// before its run), which a block shares: the groups in the order of their first bodies, each
/// group's bodies in order (`rows` is reordered so).
fn grouped_blocks<'r, 'a>(
    ctx: &Context,
    rows: &'r mut [BodyRows<'a>],
) -> Vec<&'r mut [BodyRows<'a>]> {
    let n = rows.len();
    if n == 0 {
        return Vec::new();
    }
    // Each body's order as a number (a permutation of 0, 1, 2 in base 3; `NONE` for a body
    // that fails).
    const NONE: u8 = u8::MAX;
    let code = |body: &Body| axis_order(body).map_or(NONE, |[a, b, c]| (9 * a + 3 * b + c) as u8);
    let first = rows[0].index;
    let codes: Vec<u8> = if ctx.run.parallel {
        rows.par_iter()
            .map(|r| code(&ctx.bodies[r.index]))
            .collect()
    } else {
        rows.iter().map(|r| code(&ctx.bodies[r.index])).collect()
    };
    // Each code's group: the order of its first body.
    let mut group = [u8::MAX; 256];
    let mut groups = 0;
    for &c in &codes {
        if group[usize::from(c)] == u8::MAX {
            group[usize::from(c)] = groups;
            groups += 1;
        }
    }
    let key = |i: usize| usize::from(group[usize::from(codes[i])]);
    // Each group's bodies in order, the groups one after another (a counting sort): the place
    // of each body, then the rows moved there in place, along the permutation's cycles (each
    // row moved once; a sort moved them n log n times).
    let mut sizes = vec![0usize; usize::from(groups)];
    for i in 0..n {
        sizes[key(i)] += 1;
    }
    let mut starts: Vec<usize> = sizes
        .iter()
        .scan(0, |start, &size| {
            let here = *start;
            *start += size;
            Some(here)
        })
        .collect();
    let mut place: Vec<usize> = (0..n)
        .map(|i| {
            let g = key(i);
            starts[g] += 1;
            starts[g] - 1
        })
        .collect();
    for i in 0..n {
        while place[i] != i {
            let j = place[i];
            rows.swap(i, j);
            place.swap(i, j);
        }
    }
    debug_assert!(rows.windows(2).all(|w| {
        let (a, b) = (w[0].index - first, w[1].index - first);
        (key(a), a) < (key(b), b)
    }));
    let mut blocks = Vec::with_capacity(n.div_ceil(lanes::LANES) + usize::from(groups));
    let mut rest = rows;
    for size in sizes {
        let (same, tail) = std::mem::take(&mut rest).split_at_mut(size);
        blocks.extend(same.chunks_mut(lanes::LANES));
        rest = tail;
    }
    blocks
}

/// The lane strategy: a block of at most [`lanes::LANES`] bodies (ascending indices) run in
/// SIMD lanes, torque-free by a fixed-step method; a body whose angular velocity lies outside
/// [`omega_scale`]'s range (integrated in units of a power of two by the scalar strategy, with
/// the same numbers) by `equations` alone. Returns the error of its first failing body by
/// index, if any. Each body's own checks come in the order of a run alone.
fn block_of_lanes<'a, E: Equations>(
    equations: &E,
    ctx: &Context,
    block: impl Iterator<Item = BodyRows<'a>>,
) -> Option<(usize, Error)> {
    let mut failed: Option<(usize, Error)> = None;
    let mut fail = |i: usize, error: Error| {
        ctx.failures.fail(i);
        if failed.as_ref().is_none_or(|(f, _)| i < *f) {
            failed = Some((i, error));
        }
    };
    // The bodies that start, in lanes 0..k: their job, initial state and rows.
    let mut ready: [Option<(Job, State, BodyRows)>; lanes::LANES] = Default::default();
    let mut k = 0;
    for rows in block {
        let i = rows.index;
        let job = ctx.job(i).and_then(|job| {
            if let Some(monitor) = ctx.monitor {
                monitor.check()?;
            }
            let state = start_state(&job.state)?;
            Ok((job, state))
        });
        match job {
            // An angular velocity outside [2^-256, 2^256]: integrated in units of a power of
            // two by the run alone (`driver::run_free`), the same numbers.
            Ok((_, state))
                if !matches!(ctx.run.method, Method::Splitting { .. })
                    && omega_scale(&state.omega).is_some() =>
            {
                if let Err(error) = one(equations, ctx, rows) {
                    fail(i, error);
                }
            }
            Ok((job, state)) => {
                ready[k] = Some((job, state, rows));
                k += 1;
            }
            Err(error) => fail(i, error),
        }
    }
    if k == 0 {
        return failed;
    }
    // The lanes past the bodies repeat the last one (their results are not used).
    let lane = |l: usize| ready[l.min(k - 1)].as_ref().expect("a body in lanes 0..k");
    let moments: [_; lanes::LANES] = std::array::from_fn(|l| lane(l).0.moments);
    let states: [State; lanes::LANES] = std::array::from_fn(|l| lane(l).1);
    let mut writers: [Option<(usize, &Job, Writer, &mut Stats)>; lanes::LANES] = Default::default();
    for (writer, body) in writers.iter_mut().zip(&mut ready[..k]) {
        let (job, _, rows) = body.as_mut().expect("a body in lanes 0..k");
        rows.moments
            .copy_from_slice(job.moments.moments().as_slice());
        let columns = std::mem::take(&mut rows.columns);
        let writer_of = Writer::new(&ctx.layout, columns, 0, true);
        *writer = Some((rows.index, &*job, writer_of, &mut rows.stats[0]));
    }
    let output = |j: usize, outputs: &LaneOutputs| -> Result<()> {
        ctx.look(j)?;
        for (writer, out) in writers.iter_mut().zip(outputs) {
            if let (Some((_, job, writer, _)), Some((omega, q))) = (writer, out) {
                writer.write(j, job, omega, q.as_ref(), None);
            }
        }
        Ok(())
    };
    let mut ran = lanes::integrate_lanes(
        &ctx.run.method,
        &moments[..k],
        &states[..k],
        ctx.layout.t,
        &ctx.options(None),
        output,
    );
    for (l, writer) in writers.into_iter().enumerate() {
        let Some((i, _, writer, stats)) = writer else {
            break;
        };
        let result = ran[l].take().expect("a result per lane");
        match writer.finish(result) {
            Ok(cost) => *stats = cost,
            Err(error) => fail(i, error),
        }
    }
    failed
}
