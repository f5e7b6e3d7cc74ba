//! The CUDA backend: launches the PTX of `swarf-kernels` through cudarc, which loads libcuda at run time, so the
//! binary builds and runs without any CUDA installation and uses the GPU where a driver and device exist.
//! One stream, no event tracking: every launch is ordered after the previous one.

use super::{
    Backend, Buffer, ContactInputs, DeviceInfo, Element, FieldsMut, FieldsRef, HeatInputs, PlasticInputs, SCAN_TILE,
    SphInputs,
};
use crate::kernels::neighbour::GridParams;
use crate::kernels::sph::heat::HeatParams;
use crate::kernels::sph::{CubicSpline, SphParams, Stabilisers, TensorOps};
use crate::kernels::{Dim, Real};
use crate::material::FlowModel;
use crate::{Error, Result};
use cudarc::driver::sys::{CUdevice_attribute, CUevent_flags, CUresult};
use cudarc::driver::{CudaContext, CudaFunction, CudaSlice, CudaStream, DevicePtr, DevicePtrMut, DriverError, result};
use std::ffi::c_void;
use std::marker::PhantomData;
use std::sync::Arc;

/// The (dimension, precision) suffixes of generic entry points, in `variant` order.
const VARIANTS: [&str; 4] = ["2d_f32", "2d_f64", "3d_f32", "3d_f64"];

/// Every PTX entry point the backend loads; the PTX test checks that each is present.
pub fn kernel_names() -> Vec<String> {
    let mut v: Vec<String> = [
        "swarf_count_cells",
        "swarf_scan_reduce",
        "swarf_scan_apply",
        "swarf_scatter",
        "swarf_sort_cells",
        "swarf_gather_b4",
        "swarf_gather_b8",
        "swarf_gather_b16",
        "swarf_scalar_predict",
        "swarf_scalar_correct",
        "swarf_contact_2d_f32",
        "swarf_contact_2d_f64",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for var in VARIANTS {
        for base in [
            "swarf_hash",
            "swarf_neighbour_list",
            "swarf_density",
            "swarf_sph_predict",
            "swarf_sph_correct",
            "swarf_heat_brookshaw",
            "swarf_heat_pse",
        ] {
            v.push(format!("{base}_{var}"));
        }
        for c in 0..4 {
            v.push(format!("swarf_sph_prepare_{var}_{}", prepare_suffix(c)));
        }
        for m in PLASTIC_MODELS {
            v.push(format!("swarf_plastic_{m}_{var}"));
        }
        for c in 0..8 {
            v.push(format!("swarf_sph_rates_{var}_{}", rates_suffix(c)));
        }
    }
    v
}

/// Flow-stress models in `FlowModel` order, as named in the plastic entry points.
const PLASTIC_MODELS: [&str; 9] = [
    "jc",
    "calamaz_2008",
    "calamaz_2010",
    "calamaz_2011",
    "sima_ozel_1",
    "sima_ozel_2",
    "sima_ozel_3",
    "scgl",
    "bilinear",
];

fn model_index(m: &FlowModel) -> usize {
    match m {
        FlowModel::JohnsonCook(_) => 0,
        FlowModel::Calamaz2008(_) => 1,
        FlowModel::Calamaz2010(_) => 2,
        FlowModel::Calamaz2011(_) => 3,
        FlowModel::SimaOzel1(_) => 4,
        FlowModel::SimaOzel2(_) => 5,
        FlowModel::SimaOzel3(_) => 6,
        FlowModel::Scgl(_) => 7,
        FlowModel::Bilinear(_) => 8,
    }
}

/// Suffix of the pre-pass entry for stabiliser combination c = 2·AV + AS.
fn prepare_suffix(c: usize) -> String {
    format!("v{}s{}", (c >> 1) & 1, c & 1)
}

/// Suffix of the interaction entry for combination c = 4·AV + 2·AS + XSPH.
fn rates_suffix(c: usize) -> String {
    format!("v{}s{}x{}", (c >> 2) & 1, (c >> 1) & 1, c & 1)
}

/// Most arguments of any entry point.
const MAX_ARGS: usize = 24;

/// Threads per block of the per-particle kernels.
const BLOCK: u32 = 256;

/// A typed device array; the bytes live in a `CudaSlice<u8>` so that any `Pod` type can be stored.
pub struct CudaBuf<T> {
    raw: CudaSlice<u8>,
    len: usize,
    _t: PhantomData<T>,
}

// SAFETY: the device memory is only touched through the backend's single stream.
unsafe impl<T> Send for CudaBuf<T> {}
unsafe impl<T> Sync for CudaBuf<T> {}

impl<T> Buffer<T> for CudaBuf<T> {
    fn len(&self) -> usize {
        self.len
    }
}

/// A kernel argument: scalars by value, device pointers as u64.
#[derive(Clone, Copy)]
enum Arg {
    U32(u32),
    U64(u64),
    F32(f32),
    F64(f64),
}

/// The four (dimension, precision) variants of a generic entry point: 2d_f32, 2d_f64, 3d_f32, 3d_f64.
struct Variants([CudaFunction; 4]);

fn variant<R: Real, D: Dim>() -> usize {
    (D::D == 3) as usize * 2 + (size_of::<R>() == 8) as usize
}

fn real_arg<R: Real>(x: R) -> Arg {
    if size_of::<R>() == 4 { Arg::F32(x.to_f64() as f32) } else { Arg::F64(x.to_f64()) }
}

struct Kernels {
    plastic: Vec<Variants>,
    /// 2D f32, 2D f64.
    contact: [CudaFunction; 2],
    heat_brookshaw: Variants,
    heat_pse: Variants,
    scalar_predict: CudaFunction,
    scalar_correct: CudaFunction,
    sph_prepare: Vec<Variants>,
    sph_rates: Vec<Variants>,
    sph_predict: Variants,
    sph_correct: Variants,
    hash: Variants,
    neighbour_list: Variants,
    density: Variants,
    count_cells: CudaFunction,
    scan_reduce: CudaFunction,
    scan_apply: CudaFunction,
    scatter: CudaFunction,
    sort_cells: CudaFunction,
    gather_b4: CudaFunction,
    gather_b8: CudaFunction,
    gather_b16: CudaFunction,
}

pub struct CudaBackend {
    ctx: Arc<CudaContext>,
    stream: Arc<CudaStream>,
    k: Kernels,
    info: DeviceInfo,
}

fn cuda(op: &'static str) -> impl FnOnce(DriverError) -> Error {
    move |source| Error::Cuda { op, source }
}

impl CudaBackend {
    /// Opens device `ordinal` and loads the embedded PTX; says why if that is impossible.
    pub fn new(ordinal: usize) -> Result<Self> {
        if crate::ptx::PTX.is_empty() {
            let why = crate::ptx::PTX_MISSING.unwrap_or("no PTX embedded");
            return Err(Error::GpuUnavailable(format!("this build has no GPU kernels ({})", first_line(why))));
        }
        // SAFETY: probing for the shared library has no side effects beyond loading it.
        if !unsafe { cudarc::driver::sys::is_culib_present() } {
            return Err(Error::GpuUnavailable("no CUDA driver (libcuda.so) found".into()));
        }
        let count = CudaContext::device_count().map_err(cuda("cuDeviceGetCount"))?;
        if count as usize <= ordinal {
            return Err(Error::GpuUnavailable(format!("no CUDA device {ordinal} ({count} present)")));
        }
        let ctx = CudaContext::new(ordinal).map_err(cuda("cuCtxCreate"))?;
        // SAFETY: a single stream orders all work; cross-stream event tracking is not needed.
        unsafe { ctx.disable_event_tracking() };
        let stream = ctx.default_stream();
        let cc = ctx.compute_capability().map_err(cuda("compute capability"))?;
        let (target, ptx) = crate::ptx::select(cc.0, cc.1).ok_or_else(|| {
            Error::GpuUnavailable(format!(
                "no embedded PTX target runs on compute capability {}.{} (embedded: {:?})",
                cc.0,
                cc.1,
                crate::ptx::targets()
            ))
        })?;
        let module = ctx.load_module(cudarc::nvrtc::Ptx::from_src(ptx)).map_err(cuda("loading the PTX module"))?;
        let f = |name: &str| module.load_function(name).map_err(cuda("loading a kernel"));
        let v = |base: &str, suffix: &str| -> Result<Variants> {
            let sfx = if suffix.is_empty() { String::new() } else { format!("_{suffix}") };
            Ok(Variants([
                f(&format!("{base}_2d_f32{sfx}"))?,
                f(&format!("{base}_2d_f64{sfx}"))?,
                f(&format!("{base}_3d_f32{sfx}"))?,
                f(&format!("{base}_3d_f64{sfx}"))?,
            ]))
        };
        let k = Kernels {
            plastic: PLASTIC_MODELS.iter().map(|m| v(&format!("swarf_plastic_{m}"), "")).collect::<Result<_>>()?,
            contact: [f("swarf_contact_2d_f32")?, f("swarf_contact_2d_f64")?],
            heat_brookshaw: v("swarf_heat_brookshaw", "")?,
            heat_pse: v("swarf_heat_pse", "")?,
            scalar_predict: f("swarf_scalar_predict")?,
            scalar_correct: f("swarf_scalar_correct")?,
            sph_prepare: (0..4).map(|c| v("swarf_sph_prepare", &prepare_suffix(c))).collect::<Result<_>>()?,
            sph_rates: (0..8).map(|c| v("swarf_sph_rates", &rates_suffix(c))).collect::<Result<_>>()?,
            sph_predict: v("swarf_sph_predict", "")?,
            sph_correct: v("swarf_sph_correct", "")?,
            hash: v("swarf_hash", "")?,
            neighbour_list: v("swarf_neighbour_list", "")?,
            density: v("swarf_density", "")?,
            count_cells: f("swarf_count_cells")?,
            scan_reduce: f("swarf_scan_reduce")?,
            scan_apply: f("swarf_scan_apply")?,
            scatter: f("swarf_scatter")?,
            sort_cells: f("swarf_sort_cells")?,
            gather_b4: f("swarf_gather_b4")?,
            gather_b8: f("swarf_gather_b8")?,
            gather_b16: f("swarf_gather_b16")?,
        };
        let mut driver = 0i32;
        // SAFETY: plain query into a local.
        unsafe { cudarc::driver::sys::cuDriverGetVersion(&mut driver) };
        let info = DeviceInfo {
            backend: "gpu",
            name: ctx.name().map_err(cuda("device name"))?,
            compute_capability: Some(cc),
            memory_bytes: ctx.total_mem().map_err(cuda("device memory"))?,
            driver_version: Some(driver),
            units: ctx
                .attribute(CUdevice_attribute::CU_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT)
                .map_err(cuda("multiprocessor count"))? as usize,
            ptx_target: Some(target),
        };
        Ok(CudaBackend { ctx, stream, k, info })
    }

    fn ptr<T>(&self, b: &CudaBuf<T>) -> u64 {
        let (p, _sync) = b.raw.device_ptr(&self.stream);
        p
    }

    fn ptr_mut<T>(&self, b: &mut CudaBuf<T>) -> u64 {
        let (p, _sync) = b.raw.device_ptr_mut(&self.stream);
        p
    }

    /// Launches `f` over `threads` threads in blocks of `block`. Arguments live in a stack array for the call,
    /// so a launch allocates nothing.
    fn launch(&self, f: &CudaFunction, threads: usize, block: u32, args: &[Arg]) -> Result<()> {
        if threads == 0 {
            return Ok(());
        }
        let blocks = threads.div_ceil(block as usize);
        if blocks > i32::MAX as usize || args.len() > MAX_ARGS {
            return Err(Error::Length {
                op: "kernel launch (grid too large)",
                expected: i32::MAX as usize,
                got: blocks,
            });
        }
        let mut store = [0u64; MAX_ARGS];
        for (s, a) in store.iter_mut().zip(args) {
            *s = match *a {
                Arg::U32(v) => v as u64,
                Arg::U64(v) => v,
                Arg::F32(v) => v.to_bits() as u64,
                Arg::F64(v) => v.to_bits(),
            };
        }
        let mut params = [std::ptr::null_mut::<c_void>(); MAX_ARGS];
        for (p, s) in params.iter_mut().zip(store.iter_mut()) {
            // Little-endian: a 4-byte parameter reads the low half of its 8-byte slot.
            *p = s as *mut u64 as *mut c_void;
        }
        // SAFETY: the argument list matches the entry point's signature (kept in step with kernels/src/ptx).
        unsafe {
            result::launch_kernel(
                f.cu_function(),
                (blocks as u32, 1, 1),
                (block, 1, 1),
                0,
                self.stream.cu_stream(),
                &mut params[..args.len()],
            )
        }
        .map_err(cuda("kernel launch"))
    }

    fn oom(&self, what: &'static str, bytes: usize, e: DriverError) -> Error {
        if e.0 == CUresult::CUDA_ERROR_OUT_OF_MEMORY {
            let (free, total) = self.ctx.mem_get_info().unwrap_or((0, 0));
            Error::OutOfMemory { what, bytes, free, total }
        } else {
            Error::Cuda { op: "cuMemAlloc", source: e }
        }
    }
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or(s)
}

impl Backend for CudaBackend {
    type Buf<T: Element> = CudaBuf<T>;

    fn info(&self) -> &DeviceInfo {
        &self.info
    }

    fn alloc<T: Element>(&self, n: usize, what: &'static str) -> Result<CudaBuf<T>> {
        let bytes = (n * size_of::<T>()).max(16);
        let raw = self.stream.alloc_zeros::<u8>(bytes).map_err(|e| self.oom(what, bytes, e))?;
        Ok(CudaBuf { raw, len: n, _t: PhantomData })
    }

    fn upload<T: Element>(&self, data: &[T], what: &'static str) -> Result<CudaBuf<T>> {
        let mut b = self.alloc::<T>(data.len(), what)?;
        self.write(&mut b, data)?;
        Ok(b)
    }

    fn write<T: Element>(&self, buf: &mut CudaBuf<T>, data: &[T]) -> Result<()> {
        if data.len() > buf.len {
            return Err(Error::Length { op: "write", expected: data.len(), got: buf.len });
        }
        if data.is_empty() {
            return Ok(());
        }
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mut view = buf.raw.slice_mut(0..bytes.len());
        self.stream.memcpy_htod(bytes, &mut view).map_err(cuda("copy to device"))?;
        // Pageable host memory: make sure the copy has consumed `data` before returning.
        self.stream.synchronize().map_err(cuda("synchronize"))
    }

    fn read<T: Element>(&self, buf: &CudaBuf<T>) -> Result<Vec<T>> {
        let mut out = vec![T::zeroed(); buf.len];
        if buf.len > 0 {
            let bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut out);
            let n = bytes.len();
            self.stream.memcpy_dtoh(&buf.raw.slice(0..n), bytes).map_err(cuda("copy to host"))?;
        }
        self.stream.synchronize().map_err(cuda("synchronize"))?;
        Ok(out)
    }

    fn fill_zero<T: Element>(&self, buf: &mut CudaBuf<T>, n: usize) -> Result<()> {
        if n > buf.len {
            return Err(Error::Length { op: "fill_zero", expected: n, got: buf.len });
        }
        if n > 0 {
            let mut view = buf.raw.slice_mut(0..n * size_of::<T>());
            self.stream.memset_zeros(&mut view).map_err(cuda("memset"))?;
        }
        Ok(())
    }

    fn synchronize(&self) -> Result<()> {
        self.stream.synchronize().map_err(cuda("synchronize"))
    }

    fn time_ms(&self, f: &mut dyn FnMut() -> Result<()>) -> Result<f64> {
        let a = self.ctx.new_event(Some(CUevent_flags::CU_EVENT_DEFAULT)).map_err(cuda("event"))?;
        let b = self.ctx.new_event(Some(CUevent_flags::CU_EVENT_DEFAULT)).map_err(cuda("event"))?;
        a.record(&self.stream).map_err(cuda("event record"))?;
        f()?;
        b.record(&self.stream).map_err(cuda("event record"))?;
        b.synchronize().map_err(cuda("event synchronize"))?;
        Ok(a.elapsed_ms(&b).map_err(cuda("event elapsed"))? as f64)
    }

    fn hash<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &CudaBuf<D::Vec<R>>,
        grid: &CudaBuf<GridParams>,
        keys: &mut CudaBuf<u32>,
    ) -> Result<()> {
        let args =
            [Arg::U32(n as u32), Arg::U64(self.ptr(pos)), Arg::U64(self.ptr(grid)), Arg::U64(self.ptr_mut(keys))];
        self.launch(&self.k.hash.0[variant::<R, D>()], n, BLOCK, &args)
    }

    fn count_cells(
        &self,
        n: usize,
        keys: &CudaBuf<u32>,
        counts: &mut CudaBuf<u32>,
        slots: &mut CudaBuf<u32>,
    ) -> Result<()> {
        let args = [
            Arg::U32(n as u32),
            Arg::U64(self.ptr(keys)),
            Arg::U64(self.ptr_mut(counts)),
            Arg::U64(self.ptr_mut(slots)),
        ];
        self.launch(&self.k.count_cells, n, BLOCK, &args)
    }

    fn exclusive_scan(&self, n: usize, data: &mut CudaBuf<u32>, levels: &mut [CudaBuf<u32>]) -> Result<()> {
        let tiles = n.div_ceil(SCAN_TILE);
        if tiles == 0 {
            return Ok(());
        }
        let Some((sums, rest)) = levels.split_first_mut() else {
            return Err(Error::Length { op: "exclusive_scan workspace", expected: 1, got: 0 });
        };
        if sums.len < tiles {
            return Err(Error::Length { op: "exclusive_scan workspace", expected: tiles, got: sums.len });
        }
        let d = self.ptr_mut(data);
        let s = self.ptr_mut(sums);
        // One warp per tile, four warps per block.
        self.launch(&self.k.scan_reduce, tiles * 32, 128, &[Arg::U32(n as u32), Arg::U64(d), Arg::U64(s)])?;
        if tiles == 1 {
            self.fill_zero(sums, 1)?; // the exclusive scan of one tile sum is 0
        } else {
            self.exclusive_scan(tiles, sums, rest)?;
        }
        self.launch(&self.k.scan_apply, tiles * 32, 128, &[Arg::U32(n as u32), Arg::U64(d), Arg::U64(d), Arg::U64(s)])
    }

    fn scatter(
        &self,
        n: usize,
        keys: &CudaBuf<u32>,
        slots: &CudaBuf<u32>,
        starts: &CudaBuf<u32>,
        perm: &mut CudaBuf<u32>,
    ) -> Result<()> {
        let args = [
            Arg::U32(n as u32),
            Arg::U64(self.ptr(keys)),
            Arg::U64(self.ptr(slots)),
            Arg::U64(self.ptr(starts)),
            Arg::U64(self.ptr_mut(perm)),
        ];
        self.launch(&self.k.scatter, n, BLOCK, &args)
    }

    fn sort_cells(&self, n_buckets: usize, starts: &CudaBuf<u32>, perm: &mut CudaBuf<u32>) -> Result<()> {
        let args = [Arg::U32(n_buckets as u32), Arg::U64(self.ptr(starts)), Arg::U64(self.ptr_mut(perm))];
        self.launch(&self.k.sort_cells, n_buckets, BLOCK, &args)
    }

    fn gather<T: Element>(&self, n: usize, perm: &CudaBuf<u32>, src: &CudaBuf<T>, dst: &mut CudaBuf<T>) -> Result<()> {
        let s = size_of::<T>();
        let (f, unit) = if s.is_multiple_of(16) {
            (&self.k.gather_b16, 16)
        } else if s.is_multiple_of(8) {
            (&self.k.gather_b8, 8)
        } else if s.is_multiple_of(4) {
            (&self.k.gather_b4, 4)
        } else {
            return Err(Error::Length {
                op: "gather (element size must be a multiple of 4 bytes)",
                expected: 4,
                got: s,
            });
        };
        let k = s / unit;
        let args = [
            Arg::U32(n as u32),
            Arg::U32(k as u32),
            Arg::U64(self.ptr(perm)),
            Arg::U64(self.ptr(src)),
            Arg::U64(self.ptr_mut(dst)),
        ];
        self.launch(f, n * k, BLOCK, &args)
    }

    fn neighbour_list<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &CudaBuf<D::Vec<R>>,
        grid: &CudaBuf<GridParams>,
        starts: &CudaBuf<u32>,
        support2: R,
        offsets: Option<&CudaBuf<u32>>,
        counts: &mut CudaBuf<u32>,
        list: &mut CudaBuf<u32>,
    ) -> Result<()> {
        let args = [
            Arg::U32(n as u32),
            Arg::U64(self.ptr(pos)),
            Arg::U64(self.ptr(grid)),
            Arg::U64(self.ptr(starts)),
            real_arg(support2),
            Arg::U64(offsets.map_or(0, |o| self.ptr(o))),
            Arg::U64(self.ptr_mut(counts)),
            Arg::U64(self.ptr_mut(list)),
        ];
        self.launch(&self.k.neighbour_list.0[variant::<R, D>()], n, BLOCK, &args)
    }

    fn density<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &CudaBuf<D::Vec<R>>,
        mass: &CudaBuf<R>,
        grid: &CudaBuf<GridParams>,
        starts: &CudaBuf<u32>,
        kernel: &CudaBuf<CubicSpline<R>>,
        rho: &mut CudaBuf<R>,
    ) -> Result<()> {
        let args = [
            Arg::U32(n as u32),
            Arg::U64(self.ptr(pos)),
            Arg::U64(self.ptr(mass)),
            Arg::U64(self.ptr(grid)),
            Arg::U64(self.ptr(starts)),
            Arg::U64(self.ptr(kernel)),
            Arg::U64(self.ptr_mut(rho)),
        ];
        self.launch(&self.k.density.0[variant::<R, D>()], n, BLOCK, &args)
    }

    fn sph_prepare<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        stab: Stabilisers,
        params: &CudaBuf<SphParams<R>>,
        rho: &CudaBuf<R>,
        stress: &CudaBuf<D::Sym<R>>,
        sig: &mut CudaBuf<D::Sym<R>>,
        art: Option<&mut CudaBuf<D::Sym<R>>>,
        sound: Option<&mut CudaBuf<R>>,
        temp: Option<&CudaBuf<f64>>,
    ) -> Result<()> {
        let art = if stab.stress { art.map(|a| self.ptr_mut(a)).unwrap_or(0) } else { 0 };
        let sound = if stab.viscosity { sound.map(|c| self.ptr_mut(c)).unwrap_or(0) } else { 0 };
        if (stab.stress && art == 0) || (stab.viscosity && sound == 0) {
            return Err(Error::Length { op: "sph_prepare (stabiliser buffer missing)", expected: n, got: 0 });
        }
        let c = (stab.viscosity as usize) << 1 | stab.stress as usize;
        let args = [
            Arg::U32(n as u32),
            Arg::U64(self.ptr(params)),
            Arg::U64(self.ptr(rho)),
            Arg::U64(self.ptr(stress)),
            Arg::U64(self.ptr_mut(sig)),
            Arg::U64(art),
            Arg::U64(sound),
            Arg::U64(temp.map_or(0, |t| self.ptr(t))),
        ];
        self.launch(&self.k.sph_prepare[c].0[variant::<R, D>()], n, BLOCK, &args)
    }

    fn sph_rates<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        stab: Stabilisers,
        params: &CudaBuf<SphParams<R>>,
        grid: &CudaBuf<GridParams>,
        starts: &CudaBuf<u32>,
        i: &SphInputs<'_, Self, R, D>,
        out: FieldsMut<'_, Self, R, D>,
    ) -> Result<()> {
        let art = if stab.stress { i.art.map(|a| self.ptr(a)).unwrap_or(0) } else { 0 };
        let sound = if stab.viscosity { i.sound.map(|c| self.ptr(c)).unwrap_or(0) } else { 0 };
        if (stab.stress && art == 0) || (stab.viscosity && sound == 0) {
            return Err(Error::Length { op: "sph_rates (stabiliser buffer missing)", expected: n, got: 0 });
        }
        let c = (stab.viscosity as usize) << 2 | (stab.stress as usize) << 1 | stab.xsph as usize;
        let args = [
            Arg::U32(n as u32),
            Arg::U64(self.ptr(params)),
            Arg::U64(self.ptr(grid)),
            Arg::U64(self.ptr(starts)),
            Arg::U64(self.ptr(i.pos)),
            Arg::U64(self.ptr(i.vel)),
            Arg::U64(self.ptr(i.rho)),
            Arg::U64(self.ptr(i.mass)),
            Arg::U64(self.ptr(i.stress)),
            Arg::U64(self.ptr(i.sig)),
            Arg::U64(art),
            Arg::U64(sound),
            Arg::U64(self.ptr(i.flags)),
            Arg::U64(self.ptr(i.bc_vel)),
            Arg::U64(i.contact.map_or(0, |c| self.ptr(c.0))),
            Arg::U64(i.contact.map_or(0, |c| self.ptr(c.1))),
            Arg::U64(self.ptr_mut(out.pos)),
            Arg::U64(self.ptr_mut(out.vel)),
            Arg::U64(self.ptr_mut(out.rho)),
            Arg::U64(self.ptr_mut(out.stress)),
        ];
        self.launch(&self.k.sph_rates[c].0[variant::<R, D>()], n, BLOCK, &args)
    }

    fn sph_predict<R: Real, D: Dim>(
        &self,
        n: usize,
        c: R,
        y: FieldsMut<'_, Self, R, D>,
        y0: FieldsMut<'_, Self, R, D>,
        r: FieldsRef<'_, Self, R, D>,
    ) -> Result<()> {
        let args = [
            Arg::U32(n as u32),
            real_arg(c),
            Arg::U64(self.ptr_mut(y.pos)),
            Arg::U64(self.ptr_mut(y.vel)),
            Arg::U64(self.ptr_mut(y.rho)),
            Arg::U64(self.ptr_mut(y.stress)),
            Arg::U64(self.ptr_mut(y0.pos)),
            Arg::U64(self.ptr_mut(y0.vel)),
            Arg::U64(self.ptr_mut(y0.rho)),
            Arg::U64(self.ptr_mut(y0.stress)),
            Arg::U64(self.ptr(r.pos)),
            Arg::U64(self.ptr(r.vel)),
            Arg::U64(self.ptr(r.rho)),
            Arg::U64(self.ptr(r.stress)),
        ];
        self.launch(&self.k.sph_predict.0[variant::<R, D>()], n, BLOCK, &args)
    }

    fn sph_correct<R: Real, D: Dim>(
        &self,
        n: usize,
        c: R,
        y: FieldsMut<'_, Self, R, D>,
        y0: FieldsRef<'_, Self, R, D>,
        r: FieldsRef<'_, Self, R, D>,
    ) -> Result<()> {
        let args = [
            Arg::U32(n as u32),
            real_arg(c),
            Arg::U64(self.ptr_mut(y.pos)),
            Arg::U64(self.ptr_mut(y.vel)),
            Arg::U64(self.ptr_mut(y.rho)),
            Arg::U64(self.ptr_mut(y.stress)),
            Arg::U64(self.ptr(y0.pos)),
            Arg::U64(self.ptr(y0.vel)),
            Arg::U64(self.ptr(y0.rho)),
            Arg::U64(self.ptr(y0.stress)),
            Arg::U64(self.ptr(r.pos)),
            Arg::U64(self.ptr(r.vel)),
            Arg::U64(self.ptr(r.rho)),
            Arg::U64(self.ptr(r.stress)),
        ];
        self.launch(&self.k.sph_correct.0[variant::<R, D>()], n, BLOCK, &args)
    }

    fn heat_rates<R: Real, D: Dim>(
        &self,
        n: usize,
        pse: bool,
        hp: &CudaBuf<HeatParams>,
        params: &CudaBuf<SphParams<R>>,
        grid: &CudaBuf<GridParams>,
        starts: &CudaBuf<u32>,
        i: &HeatInputs<'_, Self, R, D>,
        temp_t: &mut CudaBuf<f64>,
    ) -> Result<()> {
        let args = [
            Arg::U32(n as u32),
            Arg::U64(self.ptr(hp)),
            Arg::U64(self.ptr(params)),
            Arg::U64(self.ptr(grid)),
            Arg::U64(self.ptr(starts)),
            Arg::U64(self.ptr(i.pos)),
            Arg::U64(self.ptr(i.rho)),
            Arg::U64(self.ptr(i.mass)),
            Arg::U64(self.ptr(i.temp)),
            Arg::U64(self.ptr(i.flags)),
            Arg::U64(self.ptr(i.materials)),
            Arg::U64(self.ptr_mut(temp_t)),
        ];
        let f = if pse { &self.k.heat_pse } else { &self.k.heat_brookshaw };
        self.launch(&f.0[variant::<R, D>()], n, BLOCK, &args)
    }

    fn scalar_predict(
        &self,
        n: usize,
        c: f64,
        y: &mut CudaBuf<f64>,
        y0: &mut CudaBuf<f64>,
        yt: &CudaBuf<f64>,
    ) -> Result<()> {
        let args = [
            Arg::U32(n as u32),
            Arg::F64(c),
            Arg::U64(self.ptr_mut(y)),
            Arg::U64(self.ptr_mut(y0)),
            Arg::U64(self.ptr(yt)),
        ];
        self.launch(&self.k.scalar_predict, n, BLOCK, &args)
    }

    fn scalar_correct(
        &self,
        n: usize,
        c: f64,
        y: &mut CudaBuf<f64>,
        y0: &CudaBuf<f64>,
        yt: &CudaBuf<f64>,
    ) -> Result<()> {
        let args = [
            Arg::U32(n as u32),
            Arg::F64(c),
            Arg::U64(self.ptr_mut(y)),
            Arg::U64(self.ptr(y0)),
            Arg::U64(self.ptr(yt)),
        ];
        self.launch(&self.k.scalar_correct, n, BLOCK, &args)
    }

    fn contact<R: Real, D: Dim>(
        &self,
        n: usize,
        params: &CudaBuf<crate::kernels::contact::ContactParams>,
        tool: crate::kernels::contact::ToolState,
        a: ContactInputs<'_, Self, R, D>,
    ) -> Result<()> {
        if D::D != 2 {
            return Err(Error::Length { op: "contact (the parametric tool is 2D)", expected: 2, got: D::D });
        }
        let args = [
            Arg::U32(n as u32),
            Arg::U64(self.ptr(params)),
            Arg::F64(tool.offset[0]),
            Arg::F64(tool.offset[1]),
            Arg::F64(tool.velocity[0]),
            Arg::F64(tool.velocity[1]),
            Arg::F64(tool.dt),
            Arg::F64(tool.step),
            Arg::U64(self.ptr(a.pos)),
            Arg::U64(self.ptr(a.vel)),
            Arg::U64(self.ptr(a.mass)),
            Arg::U64(self.ptr(a.rho)),
            Arg::U64(self.ptr(a.flags)),
            Arg::U64(self.ptr_mut(a.normal)),
            Arg::U64(self.ptr_mut(a.friction)),
            Arg::U64(a.temp.map_or(0, |t| self.ptr_mut(t))),
            Arg::U64(a.materials.map_or(0, |m| self.ptr(m))),
            Arg::U64(a.yield_stress.map_or(0, |y| self.ptr(y))),
            Arg::U64(a.wear.map_or(0, |w| self.ptr_mut(w))),
        ];
        self.launch(&self.k.contact[(size_of::<R>() == 8) as usize], n, BLOCK, &args)
    }

    fn plastic_step<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        model: &FlowModel,
        model_buf: &CudaBuf<u8>,
        c: crate::kernels::sph::plastic::PlasticConsts,
        a: PlasticInputs<'_, Self, R, D>,
    ) -> Result<()> {
        if c.taylor_quinney > 0.0 && a.materials.is_none() {
            return Err(Error::Length { op: "plastic_step (thermal materials missing)", expected: 1, got: 0 });
        }
        let args = [
            Arg::U32(n as u32),
            Arg::U64(self.ptr(model_buf)),
            Arg::F64(c.shear),
            Arg::F64(c.dt),
            Arg::F64(c.taylor_quinney),
            Arg::U64(self.ptr_mut(a.stress)),
            Arg::U64(self.ptr(a.rho)),
            Arg::U64(self.ptr_mut(a.eps)),
            Arg::U64(self.ptr_mut(a.rate)),
            Arg::U64(self.ptr_mut(a.temp)),
            Arg::U64(self.ptr(a.flags)),
            Arg::U64(a.materials.map_or(0, |m| self.ptr(m))),
            Arg::U64(a.yield_stress.map_or(0, |y| self.ptr_mut(y))),
        ];
        self.launch(&self.k.plastic[model_index(model)].0[variant::<R, D>()], n, BLOCK, &args)
    }
}
