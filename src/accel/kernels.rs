//! Which of Embree's kernels answer the ray queries, and how to pin them.
//!
//! Embree compiles its traversal and intersection kernels for several instruction sets and,
//! when a device is created, picks the best one the CPU supports, unless the device's
//! configuration string names one (`isa=sse4.2`). The kernels agree on which triangle a ray
//! hits except where two candidates lie within rounding of each other (a ray through an edge
//! or a vertex, coincident faces) and on shadow rays that graze an edge; glint computes the
//! reported hit itself ([`super::triangle`]), so what is left to the kernel is that choice.
//! Pinning one instruction set that every x86-64-v2 CPU has ([`EmbreeIsa::PORTABLE`])
//! removes it as well: the same kernel code runs on every machine.
//!
//! The choice, from the most specific:
//! - [`super::BuildOptions::embree_isa`] for one structure (the tests loop over every
//!   instruction set the machine has);
//! - [`set_process_isa`], which `glint --embree-isa NAME` calls before anything is built;
//! - the environment variable `GLINT_EMBREE_ISA` (same names; read once per process);
//! - otherwise Embree's own choice ([`EmbreeIsa::Native`]).
//!
//! `GLINT_EMBREE_CONFIG` adds further options to every device's configuration string as they
//! are (`threads=4`, `verbose=1`; Embree's device documentation lists them); an `isa=` chosen
//! above comes after it and so wins.

use std::fmt;
use std::str::FromStr;
use std::sync::OnceLock;

/// An instruction set for Embree's kernels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EmbreeIsa {
    /// Embree's choice: the best kernels it has for this CPU.
    #[default]
    Native,
    /// SSE2 (every x86-64 CPU).
    Sse2,
    /// SSE4.2 (x86-64-v2).
    Sse42,
    /// AVX.
    Avx,
    /// AVX2 with FMA (x86-64-v3).
    Avx2,
    /// AVX-512 (F, CD, DQ, BW, VL: Skylake-SP and later, Zen 4 and later).
    Avx512,
}

impl EmbreeIsa {
    /// The pinned instruction sets, narrowest first.
    pub const PINNED: [EmbreeIsa; 5] = [
        EmbreeIsa::Sse2,
        EmbreeIsa::Sse42,
        EmbreeIsa::Avx,
        EmbreeIsa::Avx2,
        EmbreeIsa::Avx512,
    ];

    /// What images that must be the same on every machine are rendered with: every x86-64-v2
    /// CPU (every x86-64 CPU sold since about 2009) has SSE4.2.
    pub const PORTABLE: EmbreeIsa = EmbreeIsa::Sse42;

    /// The name glint's options and outputs use.
    pub fn name(self) -> &'static str {
        match self {
            EmbreeIsa::Native => "native",
            EmbreeIsa::Sse2 => "sse2",
            EmbreeIsa::Sse42 => "sse4.2",
            EmbreeIsa::Avx => "avx",
            EmbreeIsa::Avx2 => "avx2",
            EmbreeIsa::Avx512 => "avx512",
        }
    }

    /// The value of Embree's `isa=` option; `None` for [`EmbreeIsa::Native`]. Embree silently
    /// falls back to SSE2 on a name it does not know, so these are exactly its spellings, the
    /// same in Embree 3.13 and 4 (up to 3.12 AVX-512 was `avx512skx`, which 3.13.5 takes for
    /// SSE2, as its device properties show: the build checks them, see
    /// [`EmbreeIsa::packet_width`]).
    pub fn embree_name(self) -> Option<&'static str> {
        Some(match self {
            EmbreeIsa::Native => return None,
            EmbreeIsa::Sse2 => "sse2",
            EmbreeIsa::Sse42 => "sse4.2",
            EmbreeIsa::Avx => "avx",
            EmbreeIsa::Avx2 => "avx2",
            EmbreeIsa::Avx512 => "avx512",
        })
    }

    /// The widest ray packet Embree runs natively with these kernels (what
    /// `RTC_DEVICE_PROPERTY_NATIVE_RAY{4,8,16}_SUPPORTED` report), `None` for native: a check
    /// that a device really got the kernels asked for.
    pub fn packet_width(self) -> Option<u32> {
        match self {
            EmbreeIsa::Native => None,
            EmbreeIsa::Sse2 | EmbreeIsa::Sse42 => Some(4),
            EmbreeIsa::Avx | EmbreeIsa::Avx2 => Some(8),
            EmbreeIsa::Avx512 => Some(16),
        }
    }

    /// Whether this CPU can run these kernels (as Embree decides it: AVX2 needs FMA, BMI1,
    /// BMI2 and LZCNT too).
    pub fn cpu_supports(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::is_x86_feature_detected as has;
            match self {
                EmbreeIsa::Native | EmbreeIsa::Sse2 => true,
                EmbreeIsa::Sse42 => has!("sse4.2"),
                EmbreeIsa::Avx => has!("avx"),
                EmbreeIsa::Avx2 => {
                    has!("avx2") && has!("fma") && has!("bmi1") && has!("bmi2") && has!("lzcnt")
                }
                EmbreeIsa::Avx512 => {
                    EmbreeIsa::Avx2.cpu_supports()
                        && has!("avx512f")
                        && has!("avx512cd")
                        && has!("avx512dq")
                        && has!("avx512bw")
                        && has!("avx512vl")
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self == EmbreeIsa::Native
        }
    }

    /// Every pinned instruction set this CPU supports, narrowest first.
    pub fn supported() -> Vec<EmbreeIsa> {
        Self::PINNED
            .into_iter()
            .filter(|isa| isa.cpu_supports())
            .collect()
    }

    /// The widest instruction set this CPU supports: what Embree picks natively when it was
    /// compiled with kernels for it (distributions build all five).
    pub fn widest_supported() -> EmbreeIsa {
        Self::supported()
            .last()
            .copied()
            .unwrap_or(EmbreeIsa::Native)
    }
}

impl fmt::Display for EmbreeIsa {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for EmbreeIsa {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "native" | "" => Ok(EmbreeIsa::Native),
            "sse2" => Ok(EmbreeIsa::Sse2),
            "sse4.2" | "sse42" => Ok(EmbreeIsa::Sse42),
            "avx" => Ok(EmbreeIsa::Avx),
            "avx2" => Ok(EmbreeIsa::Avx2),
            "avx512" | "avx512skx" => Ok(EmbreeIsa::Avx512),
            other => Err(format!(
                "unknown Embree instruction set '{other}' (expected native, sse2, sse4.2, avx, \
                 avx2 or avx512)"
            )),
        }
    }
}

/// The environment variable naming the process's instruction set.
pub const ISA_VARIABLE: &str = "GLINT_EMBREE_ISA";
/// The environment variable with extra Embree device options.
pub const CONFIG_VARIABLE: &str = "GLINT_EMBREE_CONFIG";

static PROCESS_ISA: OnceLock<Result<EmbreeIsa, String>> = OnceLock::new();

/// Fixes the instruction set of every structure built later in this process without one of
/// its own. Fails if the process's choice was already made (set, or read from
/// `GLINT_EMBREE_ISA` by an earlier build) and differs.
pub fn set_process_isa(isa: EmbreeIsa) -> Result<(), String> {
    match PROCESS_ISA.get_or_init(|| Ok(isa)) {
        Ok(fixed) if *fixed == isa => Ok(()),
        Ok(fixed) => Err(format!(
            "the Embree instruction set is already fixed to {fixed} for this process"
        )),
        Err(why) => Err(why.clone()),
    }
}

/// The process's instruction set: as set by [`set_process_isa`], else `GLINT_EMBREE_ISA`,
/// else native. An unknown name in the variable is an error (so a typo never silently
/// renders with other kernels).
pub fn process_isa() -> Result<EmbreeIsa, String> {
    PROCESS_ISA
        .get_or_init(|| match std::env::var(ISA_VARIABLE) {
            Ok(value) => value.parse().map_err(|e| format!("{ISA_VARIABLE}: {e}")),
            Err(_) => Ok(EmbreeIsa::Native),
        })
        .clone()
}

/// The instruction set a structure built with `requested` uses (`None`: the process's).
pub fn resolve(requested: Option<EmbreeIsa>) -> Result<EmbreeIsa, String> {
    let isa = match requested {
        Some(isa) => isa,
        None => process_isa()?,
    };
    if !isa.cpu_supports() {
        return Err(format!(
            "this CPU cannot run Embree's {isa} kernels (it supports: {})",
            EmbreeIsa::supported()
                .iter()
                .map(|i| i.name())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    Ok(isa)
}

/// Embree's device configuration string for `isa`: `GLINT_EMBREE_CONFIG`'s options, then
/// `isa=…` when pinned.
pub fn device_config(isa: EmbreeIsa) -> String {
    let extra = std::env::var(CONFIG_VARIABLE).unwrap_or_default();
    let mut parts: Vec<String> = Vec::new();
    if !extra.trim().is_empty() {
        parts.push(extra.trim().to_string());
    }
    if let Some(name) = isa.embree_name() {
        parts.push(format!("isa={name}"));
    }
    parts.join(",")
}

/// A short description of the kernels `isa` means on this machine, for outputs and summaries:
/// `sse4.2` when pinned, `native (avx512)` otherwise (the widest this CPU supports).
pub fn describe(isa: EmbreeIsa) -> String {
    match isa {
        EmbreeIsa::Native => format!("native ({})", EmbreeIsa::widest_supported()),
        pinned => pinned.name().to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for isa in EmbreeIsa::PINNED.into_iter().chain([EmbreeIsa::Native]) {
            assert_eq!(isa.name().parse::<EmbreeIsa>(), Ok(isa));
        }
        assert!("avx3".parse::<EmbreeIsa>().is_err());
        assert_eq!(EmbreeIsa::Avx512.embree_name(), Some("avx512"));
        assert_eq!(EmbreeIsa::Native.embree_name(), None);
    }

    #[test]
    fn the_portable_set_is_supported_on_x86_64_v2() {
        // Every machine this project runs on is x86-64-v2 or later.
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("sse4.2") {
            assert!(EmbreeIsa::supported().contains(&EmbreeIsa::PORTABLE));
        }
        assert!(
            EmbreeIsa::supported()
                .first()
                .is_some_and(|i| i.cpu_supports())
        );
    }
}
