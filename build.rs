//! Builds the `swarf-kernels` crate to PTX with the pinned nightly (../shared/GPU.md "Building PTX") and embeds
//! it. Installs the nightly through rustup when it is missing, saying so. Where PTX cannot be built the host
//! still builds, without PTX, and the CUDA backend reports the reason at run time; `SWARF_REQUIRE_PTX=1` (set by
//! CI) turns that into a build error. `SWARF_NO_PTX=1` skips the PTX build (CPU-only development).

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

const NIGHTLY: &str = "nightly-2026-05-20";
/// Embedded targets: sm_80 runs on Ampere and newer (the driver JIT-compiles it for Hopper). An sm_90 build
/// measured no faster on an H200 (docs/measurements/notebook.md), so it is not embedded; add it here to build both.
const TARGETS: &[&str] = &["sm_80"];
/// The f32 LLVM flags of ../shared/GPU.md ("Floating point"): approximate f32 division and square root, and FMA
/// contraction (in every precision). Embedded as `<target>-fast`, loaded with `swarf --fast-math`
/// (docs/measurements/notebook.md measures what they change).
const FAST_FLAGS: &str =
    "-C llvm-args=-nvptx-prec-divf32=0 -C llvm-args=-nvptx-prec-sqrtf32=0 -C llvm-args=-fp-contract=fast";

fn main() {
    println!("cargo:rerun-if-changed=kernels/src");
    println!("cargo:rerun-if-changed=kernels/Cargo.toml");
    println!("cargo:rerun-if-env-changed=SWARF_REQUIRE_PTX");
    println!("cargo:rerun-if-env-changed=SWARF_NO_PTX");
    embed_materials();
    git_commit();

    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let require = env::var("SWARF_REQUIRE_PTX").is_ok_and(|v| v == "1");
    let result = if env::var("SWARF_NO_PTX").is_ok_and(|v| v == "1") {
        Err("the build set SWARF_NO_PTX=1".to_string())
    } else {
        build_all(&out)
    };
    let code = match result {
        Ok(files) => {
            let entries: Vec<String> = files
                .iter()
                .map(|(t, p)| format!("    ({t:?}, include_str!({:?})),", p.display().to_string()))
                .collect();
            format!(
                "/// PTX embedded at build time, by target.\npub const PTX: &[(&str, &str)] = &[\n{}\n];\n\
                 /// Why no PTX is embedded, if none is.\npub const PTX_MISSING: Option<&str> = None;\n",
                entries.join("\n")
            )
        }
        Err(why) => {
            if require {
                panic!("SWARF_REQUIRE_PTX=1 but the PTX build failed: {why}");
            }
            println!("cargo:warning=swarf is built without GPU kernels: {}", first_line(&why));
            format!(
                "/// PTX embedded at build time, by target.\npub const PTX: &[(&str, &str)] = &[];\n\
                 /// Why no PTX is embedded, if none is.\npub const PTX_MISSING: Option<&str> = Some({why:?});\n"
            )
        }
    };
    fs::write(out.join("ptx_embed.rs"), code).expect("write ptx_embed.rs");
}

/// The material library `cases/materials/*.toml`, embedded so that an installed swarf has it
/// (host/material/search.rs reads `materials_embed.rs`).
fn embed_materials() {
    println!("cargo:rerun-if-changed=cases/materials");
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let dir = manifest.join("cases/materials");
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    let entries: Vec<String> = files
        .iter()
        .map(|p| {
            let name = p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            format!("    ({name:?}, include_str!({:?})),", p.display().to_string())
        })
        .collect();
    let code = format!(
        "/// cases/materials/*.toml at build time: (file name, text), sorted by name.\n\
         pub const EMBEDDED: &[(&str, &str)] = &[\n{}\n];\n",
        entries.join("\n")
    );
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::write(out.join("materials_embed.rs"), code).expect("write materials_embed.rs");
}

/// `SWARF_GIT_COMMIT`: the short commit hash of the source tree, or "unknown" without git (a source archive).
/// Reruns when HEAD or the branch it names moves.
fn git_commit() {
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .filter(|s| !s.is_empty())
    };
    for path in ["HEAD", "packed-refs"].map(String::from).into_iter().chain(git(&["symbolic-ref", "-q", "HEAD"])) {
        // A missing file would rerun the build script on every build: name only those that exist.
        if let Some(p) = git(&["rev-parse", "--git-path", &path]).filter(|p| Path::new(p).exists()) {
            println!("cargo:rerun-if-changed={p}");
        }
    }
    let commit = git(&["rev-parse", "--short", "HEAD"]).unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=SWARF_GIT_COMMIT={commit}");
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or(s)
}

fn build_all(out: &Path) -> Result<Vec<(String, PathBuf)>, String> {
    ensure_nightly()?;
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").map_err(|e| e.to_string())?);
    // target/<profile>/build/swarf-*/out -> target/ptx, shared by debug and release builds.
    let target_root = out.ancestors().nth(4).map(|p| p.join("ptx")).unwrap_or_else(|| manifest.join("target/ptx"));
    let builds: Vec<(String, &str, &str)> =
        TARGETS.iter().flat_map(|t| [(t.to_string(), *t, ""), (format!("{t}-fast"), *t, FAST_FLAGS)]).collect();
    // The builds at once, each in its own target folder: each is one rustc on one core for about a minute
    // (core, then the kernels crate's LLVM), so on CI's two cores the pair takes the time of one.
    let built: Vec<Result<PathBuf, String>> = std::thread::scope(|s| {
        let handles: Vec<_> = builds
            .iter()
            .map(|(name, t, flags)| {
                let (manifest, dir) = (&manifest, target_root.join(name));
                s.spawn(move || build_one(manifest, &dir, t, flags))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap_or_else(|_| Err("a PTX build panicked".to_string()))).collect()
    });
    let mut files = Vec::new();
    for ((name, _, _), ptx) in builds.into_iter().zip(built) {
        let ptx = ptx?;
        let dst = out.join(format!("swarf_{name}.ptx"));
        fs::copy(&ptx, &dst).map_err(|e| format!("copy {}: {e}", ptx.display()))?;
        files.push((name, dst));
    }
    Ok(files)
}

/// A command with the outer build's environment removed, so that the child cargo uses the nightly and its own
/// settings (../shared/GPU.md: every CARGO*, RUSTC*, DEP_* variable and RUSTUP_TOOLCHAIN).
fn clean_command(program: &str) -> Command {
    let mut c = Command::new(program);
    for (k, _) in env::vars_os() {
        let k = k.to_string_lossy().to_string();
        if k.starts_with("CARGO")
            || k.starts_with("RUSTC")
            || k.starts_with("DEP_")
            || k == "RUSTUP_TOOLCHAIN"
            || k == "RUSTFLAGS"
            || k == "RUSTDOCFLAGS"
        {
            c.env_remove(&k);
        }
    }
    c
}

fn ensure_nightly() -> Result<(), String> {
    let probe = clean_command("rustup").args(["run", NIGHTLY, "rustc", "--version"]).output();
    match probe {
        Err(e) => return Err(format!("rustup not found ({e}); install rustup to build the GPU kernels")),
        Ok(o) if o.status.success() => {}
        Ok(_) => {
            println!("cargo:warning=installing the Rust toolchain {NIGHTLY} (rust-src) for the GPU kernels");
            let st = clean_command("rustup")
                .args(["toolchain", "install", NIGHTLY, "--profile", "minimal", "--component", "rust-src"])
                .status()
                .map_err(|e| format!("rustup toolchain install failed to start: {e}"))?;
            if !st.success() {
                return Err(format!("`rustup toolchain install {NIGHTLY}` failed ({st})"));
            }
        }
    }
    // The toolchain may exist without rust-src (needed by -Zbuild-std); adding it is idempotent.
    let st = clean_command("rustup")
        .args(["component", "add", "rust-src", "--toolchain", NIGHTLY])
        .output()
        .map_err(|e| format!("rustup component add failed to start: {e}"))?;
    if !st.status.success() {
        return Err(format!(
            "`rustup component add rust-src --toolchain {NIGHTLY}` failed: {}",
            String::from_utf8_lossy(&st.stderr)
        ));
    }
    Ok(())
}

fn build_one(manifest: &Path, target_dir: &Path, sm: &str, flags: &str) -> Result<PathBuf, String> {
    let o = clean_command("rustup")
        .current_dir(manifest)
        .env("RUSTFLAGS", format!("-Zcross-crate-inline-threshold=always -C panic=abort {flags}").trim())
        .args(["run", NIGHTLY, "cargo", "rustc", "--release", "--locked", "-p", "swarf-kernels"])
        .args(["--target", "nvptx64-nvidia-cuda", "-Zbuild-std=core", "--target-dir"])
        .arg(target_dir)
        .args(["--", "--emit=asm", "-C"])
        .arg(format!("target-cpu={sm}"))
        .output()
        .map_err(|e| format!("could not start the nightly cargo: {e}"))?;
    if !o.status.success() {
        return Err(format!("PTX build for {sm} failed:\n{}", String::from_utf8_lossy(&o.stderr)));
    }
    let deps = target_dir.join("nvptx64-nvidia-cuda/release/deps");
    let newest = fs::read_dir(&deps)
        .map_err(|e| format!("{}: {e}", deps.display()))?
        .filter_map(|e| e.ok())
        .filter(|e| {
            let n = e.file_name().to_string_lossy().to_string();
            n.starts_with("swarf_kernels-") && n.ends_with(".s")
        })
        .max_by_key(|e| e.metadata().and_then(|m| m.modified()).ok())
        .ok_or_else(|| format!("no swarf_kernels-*.s under {}", deps.display()))?;
    Ok(newest.path())
}
