//! A [`GranularLaw`] by name, from JSON: the sub-models are named as in LAMMPS
//! `pair_style granular` (`docs/laws.md` lists every name and parameter):
//!
//! ```json
//! {"normal": {"model": "hertz/material", "E": 7e10, "nu": 0.33},
//!  "damping": {"model": "tsuji", "e": 0.5},
//!  "tangential": {"model": "mindlin", "mu": 0.3},
//!  "rolling": {"model": "elastic_plastic", "mu_r": 0.05},
//!  "vdw": {"hamaker": 6.5e-20, "h_min": 4e-10, "cutoff": 1e-7}}
//! ```
//!
//! [`GranularSpec::build`] checks every value (finite; E, k > 0; −1 < ν < 0.5;
//! 0 < e ≤ 1; γ, A, μ ≥ 0; k₂ ≥ k₁; h_cut > h_min > 0) and [`GranularLaw::from_json`]
//! turns serde's errors (missing field, unknown model with the known names, wrong type)
//! into a [`LawError`] naming the file, the field path and the reason. `damping` defaults
//! to `none`; `rolling`, `twisting` (`{"model": "marshall"}` or `{"model": "sds", "k_tw",
//! "eta_tw", "mu_tw"}`) and `vdw` are optional; `"limit_damping": true` clips the dashpot
//! so that it never pulls (LAMMPS' keyword).

use crate::normal::Material;
use crate::{
    Damping, GranularLaw, LawError, Normal, Rolling, RollingResistance, Tangential, Twisting,
    VanDerWaals, H_MIN_DEFAULT,
};
use serde::{Deserialize, Serialize};

/// Normal sub-model by name.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(tag = "model", deny_unknown_fields)]
pub enum NormalSpec {
    /// F = k_n δ.
    #[serde(rename = "hooke")]
    Hooke {
        /// k_n (N/m).
        kn: f64,
    },
    /// F = k_n δ^{3/2}.
    #[serde(rename = "hertz")]
    Hertz {
        /// k_n (N/m^{3/2}).
        kn: f64,
    },
    /// F = (4/3) E* √R* δ^{3/2}.
    #[serde(rename = "hertz/material")]
    HertzMaterial {
        /// Young's modulus (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Poisson's ratio.
        nu: f64,
    },
    /// Hertz − 4πγR*.
    #[serde(rename = "dmt")]
    Dmt {
        /// Young's modulus (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Poisson's ratio.
        nu: f64,
        /// Surface energy γ (J/m²).
        gamma: f64,
    },
    /// Johnson–Kendall–Roberts.
    #[serde(rename = "jkr")]
    Jkr {
        /// Young's modulus (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Poisson's ratio.
        nu: f64,
        /// Surface energy γ (J/m²).
        gamma: f64,
    },
    /// Walton–Braun hysteretic spring, e = √(k₁/k₂).
    #[serde(rename = "walton_braun")]
    WaltonBraun {
        /// Loading stiffness k₁ (N/m).
        k1: f64,
        /// Unloading stiffness k₂ ≥ k₁ (N/m).
        k2: f64,
    },
}

/// Damping sub-model by name.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(tag = "model", deny_unknown_fields)]
pub enum DampingSpec {
    /// No dashpot.
    #[serde(rename = "none")]
    None,
    /// c = γ.
    #[serde(rename = "velocity")]
    Velocity {
        /// γ (N·s/m).
        gamma: f64,
    },
    /// c = γ m*.
    #[serde(rename = "mass_velocity")]
    MassVelocity {
        /// γ (1/s).
        gamma: f64,
    },
    /// c = η a.
    #[serde(rename = "viscoelastic")]
    Viscoelastic {
        /// η (Pa·s).
        eta: f64,
    },
    /// c = −2√(5/6) β(e) √(m* S_n).
    #[serde(rename = "tsuji")]
    Tsuji {
        /// Coefficient of restitution, 0 < e ≤ 1.
        e: f64,
    },
    /// c calibrated for e (exact for hooke; clipped Hertz otherwise).
    #[serde(rename = "coeff_restitution")]
    CoeffRestitution {
        /// Coefficient of restitution, 0 < e ≤ 1.
        e: f64,
    },
}

/// Tangential sub-model by name.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(tag = "model", deny_unknown_fields)]
pub enum TangentialSpec {
    /// F_t = −min(γ_t|v_t|, μF_n) v̂_t.
    #[serde(rename = "linear_nohistory")]
    LinearNoHistory {
        /// γ_t (N·s/m).
        gamma_t: f64,
        /// Friction coefficient.
        mu: f64,
    },
    /// Spring k_t with history, dashpot x_γ,t × the normal one.
    #[serde(rename = "linear_history")]
    LinearHistory {
        /// k_t (N/m).
        kt: f64,
        /// Friction coefficient.
        mu: f64,
        /// Tangential dashpot factor (default 0).
        #[serde(default)]
        xgammat: f64,
    },
    /// k_t = 8G*a (G* from the normal model's E, ν).
    #[serde(rename = "mindlin")]
    Mindlin {
        /// Friction coefficient.
        mu: f64,
        /// Tangential dashpot factor (default 0).
        #[serde(default)]
        xgammat: f64,
    },
    /// mindlin, the history scaled by a/a_prev when a shrinks.
    #[serde(rename = "mindlin_rescale")]
    MindlinRescale {
        /// Friction coefficient.
        mu: f64,
        /// Tangential dashpot factor (default 0).
        #[serde(default)]
        xgammat: f64,
    },
    /// mindlin on an incremental force history.
    #[serde(rename = "mindlin/force")]
    MindlinForce {
        /// Friction coefficient.
        mu: f64,
        /// Tangential dashpot factor (default 0).
        #[serde(default)]
        xgammat: f64,
    },
    /// mindlin/force, the history scaled by a/a_prev when a shrinks.
    #[serde(rename = "mindlin_rescale/force")]
    MindlinRescaleForce {
        /// Friction coefficient.
        mu: f64,
        /// Tangential dashpot factor (default 0).
        #[serde(default)]
        xgammat: f64,
    },
    /// Mindlin–Deresiewicz partial slip (G* from the normal model's E, ν).
    #[serde(rename = "mindlin/deresiewicz")]
    MindlinDeresiewicz {
        /// Friction coefficient.
        mu: f64,
    },
}

fn default_stiffness_factor() -> f64 {
    2.25
}

/// Rolling sub-model by name.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(tag = "model", deny_unknown_fields)]
pub enum RollingSpec {
    /// Ai et al. 2011 model A.
    #[serde(rename = "constant_torque")]
    ConstantTorque {
        /// Rolling friction coefficient μ_r.
        mu_r: f64,
    },
    /// Ai et al. 2011 model C (elastic–plastic spring).
    #[serde(rename = "elastic_plastic")]
    ElasticPlastic {
        /// Rolling friction coefficient μ_r.
        mu_r: f64,
        /// c_k of k_r = c_k k_n μ_r² R*² (default 2.25).
        #[serde(default = "default_stiffness_factor")]
        stiffness_factor: f64,
    },
}

/// Twisting sub-model by name.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(tag = "model", deny_unknown_fields)]
pub enum TwistingSpec {
    /// Coefficients from the tangential model (Marshall 2009).
    #[serde(rename = "marshall")]
    Marshall,
    /// Given spring, dashpot and friction.
    #[serde(rename = "sds")]
    Sds {
        /// k_tw (N·m/rad).
        k_tw: f64,
        /// η_tw (N·m·s/rad).
        eta_tw: f64,
        /// μ_tw (m).
        mu_tw: f64,
    },
}

/// Van der Waals block.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct VdwSpec {
    /// Hamaker constant A (J).
    pub hamaker: f64,
    /// Minimum separation (m), default 4e-10.
    #[serde(default)]
    pub h_min: Option<f64>,
    /// Cut-off separation (m).
    pub cutoff: f64,
    /// Cylinder length (m): the 2D parallel-cylinder form × length instead of spheres.
    #[serde(default)]
    pub length: Option<f64>,
}

/// A composed law by name (module docs).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct GranularSpec {
    pub normal: NormalSpec,
    #[serde(default = "no_damping")]
    pub damping: DampingSpec,
    pub tangential: TangentialSpec,
    #[serde(default)]
    pub rolling: Option<RollingSpec>,
    #[serde(default)]
    pub twisting: Option<TwistingSpec>,
    #[serde(default)]
    pub vdw: Option<VdwSpec>,
    /// Clip the dashpot so that it never pulls (LAMMPS `limit_damping`); default false.
    #[serde(default)]
    pub limit_damping: bool,
}

fn no_damping() -> DampingSpec {
    DampingSpec::None
}

fn finite(path: &str, v: f64) -> Result<f64, LawError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(LawError::invalid(
            path,
            format!("must be a finite number, got {v}"),
        ))
    }
}

fn positive(path: &str, v: f64) -> Result<f64, LawError> {
    if finite(path, v)? > 0.0 {
        Ok(v)
    } else {
        Err(LawError::invalid(path, format!("must be > 0, got {v}")))
    }
}

fn non_negative(path: &str, v: f64, what: &str) -> Result<f64, LawError> {
    if finite(path, v)? >= 0.0 {
        Ok(v)
    } else {
        Err(LawError::invalid(
            path,
            format!("{what} must be ≥ 0, got {v}"),
        ))
    }
}

fn restitution(path: &str, e: f64) -> Result<f64, LawError> {
    if finite(path, e)? > 0.0 && e <= 1.0 {
        Ok(e)
    } else {
        Err(LawError::invalid(
            path,
            format!("the coefficient of restitution must be in (0, 1], got {e}"),
        ))
    }
}

fn material(prefix: &str, e: f64, nu: f64) -> Result<Material, LawError> {
    positive(&format!("{prefix}.E"), e)?;
    let p = format!("{prefix}.nu");
    if !(finite(&p, nu)? > -1.0 && nu < 0.5) {
        return Err(LawError::invalid(
            p,
            format!("Poisson's ratio must be in (−1, 0.5), got {nu}"),
        ));
    }
    Ok(Material::identical(e, nu))
}

impl NormalSpec {
    /// The checked sub-model.
    pub fn build(&self) -> Result<Normal, LawError> {
        let n = "normal";
        Ok(match *self {
            NormalSpec::Hooke { kn } => Normal::Hooke {
                kn: positive("normal.kn", kn)?,
            },
            NormalSpec::Hertz { kn } => Normal::Hertz {
                kn: positive("normal.kn", kn)?,
            },
            NormalSpec::HertzMaterial { e, nu } => Normal::HertzMaterial(material(n, e, nu)?),
            NormalSpec::Dmt { e, nu, gamma } => Normal::Dmt {
                material: material(n, e, nu)?,
                gamma: non_negative("normal.gamma", gamma, "the surface energy")?,
            },
            NormalSpec::Jkr { e, nu, gamma } => Normal::Jkr {
                material: material(n, e, nu)?,
                gamma: non_negative("normal.gamma", gamma, "the surface energy")?,
            },
            NormalSpec::WaltonBraun { k1, k2 } => {
                positive("normal.k1", k1)?;
                positive("normal.k2", k2)?;
                if k2 < k1 {
                    return Err(LawError::invalid(
                        "normal.k2",
                        format!("k2 must be ≥ k1 (e = √(k1/k2) ≤ 1), got k1 = {k1}, k2 = {k2}"),
                    ));
                }
                Normal::WaltonBraun { k1, k2 }
            }
        })
    }
}

impl DampingSpec {
    /// The checked sub-model for the normal sub-model `normal`.
    pub fn build(&self, normal: &Normal) -> Result<Damping, LawError> {
        Ok(match *self {
            DampingSpec::None => Damping::None,
            DampingSpec::Velocity { gamma } => Damping::Velocity {
                gamma: non_negative("damping.gamma", gamma, "the damping")?,
            },
            DampingSpec::MassVelocity { gamma } => Damping::MassVelocity {
                gamma: non_negative("damping.gamma", gamma, "the damping")?,
            },
            DampingSpec::Viscoelastic { eta } => Damping::Viscoelastic {
                eta: non_negative("damping.eta", eta, "the damping")?,
            },
            DampingSpec::Tsuji { e } => Damping::tsuji(restitution("damping.e", e)?),
            DampingSpec::CoeffRestitution { e } => {
                Damping::coeff_restitution(restitution("damping.e", e)?, normal.is_linear())
            }
        })
    }
}

impl TangentialSpec {
    /// The checked sub-model for the normal sub-model `normal`.
    pub fn build(&self, normal: &Normal) -> Result<Tangential, LawError> {
        let mu = |m: f64| non_negative("tangential.mu", m, "the friction coefficient");
        let g_star = |name: &str| {
            normal.material().map(|m| m.g_star).ok_or_else(|| {
                LawError::invalid(
                    "tangential.model",
                    format!(
                        "{name} takes G* from the normal model's E and nu: use hertz/material, \
                         dmt or jkr"
                    ),
                )
            })
        };
        Ok(match *self {
            TangentialSpec::LinearNoHistory { gamma_t, mu: m } => Tangential::LinearNoHistory {
                gamma_t: non_negative("tangential.gamma_t", gamma_t, "the damping")?,
                mu: mu(m)?,
            },
            TangentialSpec::LinearHistory { kt, mu: m, xgammat } => Tangential::LinearHistory {
                kt: positive("tangential.kt", kt)?,
                xgammat: non_negative("tangential.xgammat", xgammat, "the damping factor")?,
                mu: mu(m)?,
            },
            TangentialSpec::Mindlin { mu: m, xgammat }
            | TangentialSpec::MindlinRescale { mu: m, xgammat }
            | TangentialSpec::MindlinForce { mu: m, xgammat }
            | TangentialSpec::MindlinRescaleForce { mu: m, xgammat } => {
                let (name, force, rescale) = match self {
                    TangentialSpec::MindlinRescale { .. } => ("mindlin_rescale", false, true),
                    TangentialSpec::MindlinForce { .. } => ("mindlin/force", true, false),
                    TangentialSpec::MindlinRescaleForce { .. } => {
                        ("mindlin_rescale/force", true, true)
                    }
                    _ => ("mindlin", false, false),
                };
                Tangential::Mindlin {
                    g_star: g_star(name)?,
                    xgammat: non_negative("tangential.xgammat", xgammat, "the damping factor")?,
                    mu: mu(m)?,
                    force,
                    rescale,
                }
            }
            TangentialSpec::MindlinDeresiewicz { mu: m } => Tangential::MindlinDeresiewicz {
                g_star: g_star("mindlin/deresiewicz")?,
                mu: mu(m)?,
            },
        })
    }
}

impl RollingSpec {
    /// The checked sub-model.
    pub fn build(&self) -> Result<Rolling, LawError> {
        let mu_r = |m: f64| non_negative("rolling.mu_r", m, "the rolling friction");
        Ok(match *self {
            RollingSpec::ConstantTorque { mu_r: m } => Rolling::ConstantTorque { mu_r: mu_r(m)? },
            RollingSpec::ElasticPlastic {
                mu_r: m,
                stiffness_factor,
            } => Rolling::ElasticPlastic(RollingResistance {
                mu_r: mu_r(m)?,
                stiffness_factor: non_negative(
                    "rolling.stiffness_factor",
                    stiffness_factor,
                    "the stiffness factor",
                )?,
            }),
        })
    }
}

impl TwistingSpec {
    /// The checked sub-model.
    pub fn build(&self) -> Result<Twisting, LawError> {
        Ok(match *self {
            TwistingSpec::Marshall => Twisting::Marshall,
            TwistingSpec::Sds {
                k_tw,
                eta_tw,
                mu_tw,
            } => Twisting::Sds {
                k_tw: non_negative("twisting.k_tw", k_tw, "the twisting stiffness")?,
                eta_tw: non_negative("twisting.eta_tw", eta_tw, "the twisting damping")?,
                mu_tw: non_negative("twisting.mu_tw", mu_tw, "the twisting friction")?,
            },
        })
    }
}

impl VdwSpec {
    /// The checked sub-model.
    pub fn build(&self) -> Result<VanDerWaals, LawError> {
        let hamaker = non_negative("vdw.hamaker", self.hamaker, "the Hamaker constant")?;
        let h_min = positive("vdw.h_min", self.h_min.unwrap_or(H_MIN_DEFAULT))?;
        let cutoff = finite("vdw.cutoff", self.cutoff)?;
        if cutoff <= h_min {
            return Err(LawError::invalid(
                "vdw.cutoff",
                format!("must be > h_min = {h_min}, got {cutoff}"),
            ));
        }
        let length = match self.length {
            Some(l) => Some(positive("vdw.length", l)?),
            None => None,
        };
        Ok(VanDerWaals {
            hamaker,
            h_min,
            cutoff,
            length,
        })
    }
}

impl GranularSpec {
    /// The checked law.
    pub fn build(&self) -> Result<GranularLaw, LawError> {
        let normal = self.normal.build()?;
        Ok(GranularLaw {
            normal,
            damping: self.damping.build(&normal)?,
            tangential: self.tangential.build(&normal)?,
            rolling: self.rolling.as_ref().map(RollingSpec::build).transpose()?,
            twisting: self
                .twisting
                .as_ref()
                .map(TwistingSpec::build)
                .transpose()?,
            vdw: self.vdw.as_ref().map(VdwSpec::build).transpose()?,
            limit_damping: self.limit_damping,
        })
    }

    /// Read a spec from JSON text; `file` names the source in errors.
    pub fn from_json(text: &str, file: Option<&str>) -> Result<GranularSpec, LawError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let r: Result<GranularSpec, _> = serde_path_to_error::deserialize(&mut *de);
        let spec = r.map_err(|e| {
            let mut path = e.path().to_string();
            if path == "." {
                path.clear();
            }
            let reason = e.inner().to_string();
            let join = |p: &str, f: &str| {
                if p.is_empty() {
                    f.to_string()
                } else {
                    format!("{p}.{f}")
                }
            };
            // Point at the field itself where serde names it.
            let named = |prefix: &str| {
                reason
                    .strip_prefix(prefix)
                    .and_then(|r| r.split('`').next())
                    .map(str::to_string)
            };
            if let Some(f) = named("missing field `").or_else(|| named("unknown field `")) {
                path = join(&path, &f);
            } else if reason.starts_with("unknown variant") && !path.ends_with("model") {
                path = join(&path, "model");
            }
            if path.is_empty() {
                path = "(top level)".into();
            }
            let err = LawError::invalid(path, reason);
            match file {
                Some(f) => err.in_file(f),
                None => err,
            }
        })?;
        de.end().map_err(|e| {
            let err = LawError::invalid("(top level)", e.to_string());
            match file {
                Some(f) => err.in_file(f),
                None => err,
            }
        })?;
        Ok(spec)
    }
}

impl GranularLaw {
    /// A checked law from JSON text (module docs); `file` names the source in errors.
    ///
    /// ```
    /// use dem_laws::{ContactLaw, GranularHistory, GranularLaw, Kin};
    /// let law = GranularLaw::from_json(
    ///     r#"{"normal": {"model": "hertz/material", "E": 7e10, "nu": 0.33},
    ///         "damping": {"model": "tsuji", "e": 0.5},
    ///         "tangential": {"model": "mindlin", "mu": 0.3}}"#,
    ///     None,
    /// )?;
    /// let k = Kin { delta: 1e-6, vn: 0.0, vt: 0.0, m_eff: 1e-3, r_eff: 1e-3, dt: 1e-7 };
    /// let mut h = GranularHistory::<f64>::default();
    /// let out = law.force::<false>(&k, &mut h);
    /// assert!(out.f_n > 0.0);
    ///
    /// let err = GranularLaw::from_json(
    ///     r#"{"normal": {"model": "hertz/material", "E": 7e10, "nu": 0.7},
    ///         "tangential": {"model": "mindlin", "mu": 0.3}}"#,
    ///     Some("law.json"),
    /// )
    /// .unwrap_err();
    /// assert!(err.to_string().starts_with("law.json: normal.nu: "));
    /// # Ok::<(), dem_laws::LawError>(())
    /// ```
    pub fn from_json(text: &str, file: Option<&str>) -> Result<GranularLaw, LawError> {
        let spec = GranularSpec::from_json(text, file)?;
        spec.build().map_err(|e| match file {
            Some(f) => e.in_file(f),
            None => e,
        })
    }

    /// A checked law from a JSON file.
    pub fn from_json_file(path: &std::path::Path) -> Result<GranularLaw, LawError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| LawError::Io {
            file: name.clone(),
            source,
        })?;
        GranularLaw::from_json(&text, Some(&name))
    }
}

#[cfg(all(test, feature = "schema"))]
mod tests {
    #[test]
    fn the_schema_names_every_model() {
        let s = serde_json::to_string(&schemars::schema_for!(super::GranularSpec)).unwrap();
        for name in [
            "hertz/material",
            "walton_braun",
            "coeff_restitution",
            "mindlin/deresiewicz",
            "constant_torque",
            "hamaker",
        ] {
            assert!(s.contains(name), "{name}");
        }
    }
}
