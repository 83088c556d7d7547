//! The HHT-α method (Hilber, Hughes & Taylor 1977; Hughes, The Finite Element Method, 1987, §9.3)
//! and the motion a dynamic stage carries from step to step.
//!
//! With Newmark's relations over a step of length h,
//!
//! ```text
//! a₁ = c0·(u₁ − u₀) − c2·v₀ − c3·a₀            c0 = 1/(βh²), c2 = 1/(βh), c3 = 1/(2β) − 1
//! v₁ = c1·(u₁ − u₀) + c4·v₀ + c5·a₀            c1 = γ/(βh),  c4 = 1 − γ/β, c5 = h·(1 − γ/(2β))
//! ```
//!
//! and γ = 1/2 − α, β = (1 − α)²/4 (α ∈ [−1/3, 0]; α = 0 is the trapezoidal rule), the HHT
//! equation of motion, M·a₁ + (1 + α)·(C·v₁ + R(u₁)) − α·(C·v₀ + R(u₀)) = 0 with R the static
//! residual (internal forces, the multipliers' Cᵀλ, less the applied and ground-motion forces),
//! divided by 1 + α, reads
//!
//! ```text
//! R(u₁) + D·u₁ + h = 0,   D = (c0/(1 + α) + a0·c1)·M + c1·(a1·K + B),
//! ```
//!
//! with C = a0·M + a1·K + B, Rayleigh's damping and the absorbing sides' dashpots B.
//!
//! with h made of the step's start alone. So a time step is a static increment with the extra
//! linear stiffness D and a constant force −h: the interfaces' laws, release and re-association,
//! and the soil's yielding take it as they take a load step, and the constraint rows hold at the
//! step's end. R(u₀) is carried from the step before (zero where the stage starts from a static
//! equilibrium).

use crate::assembly::inertia::Inertia;
use crate::assembly::ElementMatrices;

/// The HHT-α method's parameters.
#[derive(Debug, Clone, Copy)]
pub struct Hht {
    pub alpha: f64,
    pub beta: f64,
    pub gamma: f64,
}

impl Hht {
    pub fn new(alpha: f64) -> Hht {
        Hht { alpha, beta: (1.0 - alpha) * (1.0 - alpha) / 4.0, gamma: 0.5 - alpha }
    }

    /// The coefficients of a step of length `h`.
    pub fn step(&self, h: f64) -> StepCoefficients {
        let Hht { alpha, beta, gamma } = *self;
        StepCoefficients {
            c0: 1.0 / (beta * h * h),
            c1: gamma / (beta * h),
            c2: 1.0 / (beta * h),
            c3: 1.0 / (2.0 * beta) - 1.0,
            c4: 1.0 - gamma / beta,
            c5: h * (1.0 - gamma / (2.0 * beta)),
            inertia_weight: 1.0 / (1.0 + alpha),
            carried: alpha / (1.0 + alpha),
        }
    }
}

/// Newmark's relations over one step, and the HHT weights.
#[derive(Debug, Clone, Copy)]
pub struct StepCoefficients {
    pub c0: f64,
    pub c1: f64,
    pub c2: f64,
    pub c3: f64,
    pub c4: f64,
    pub c5: f64,
    /// 1/(1 + α): the weight of M·a₁.
    pub inertia_weight: f64,
    /// α/(1 + α): the weight of the step start's C·v₀ + R(u₀).
    pub carried: f64,
}

impl StepCoefficients {
    /// D's coefficients of M, of the elastic K and of the dashpots B, with Rayleigh's `[a0, a1]`.
    pub fn operator(&self, rayleigh: [f64; 2]) -> (f64, f64, f64) {
        (self.c0 * self.inertia_weight + rayleigh[0] * self.c1, rayleigh[1] * self.c1, self.c1)
    }
}

/// What a dynamic stage carries from step to step: time, the velocities and accelerations
/// (relative to a rigid base, or absolute over a compliant one), the ground's acceleration, and the
/// static residual R(u) at the step.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// [s] from the stage's start.
    pub time: f64,
    pub velocity: Vec<f64>,
    pub acceleration: Vec<f64>,
    /// The base's acceleration (x, y) at `time`.
    pub ground: [f64; 2],
    /// The velocities and accelerations are relative to a rigid base (add `ground` for the
    /// absolute acceleration); otherwise absolute (a compliant base).
    pub relative: bool,
    pub residual: Vec<f64>,
}

impl Motion {
    /// At rest at the stage's start, in static equilibrium.
    pub fn at_rest(dofs: usize, relative: bool) -> Motion {
        Motion {
            time: 0.0,
            velocity: vec![0.0; dofs],
            acceleration: vec![0.0; dofs],
            ground: [0.0; 2],
            relative,
            residual: vec![0.0; dofs],
        }
    }
}

/// One step from `motion` (at displacements `u0`) under the coefficients `k` and Rayleigh's
/// `[a0, a1]`: what the step's end follows from its displacements u₁, as a₁ = c0·u₁ + p and
/// v₁ = c1·u₁ + q, and the constant force h of the step's equation.
pub struct StepStart {
    p: Vec<f64>,
    q: Vec<f64>,
    pub constant: Vec<f64>,
}

/// The soil's mass and damping, as a step applies them: M·x and C·x = a0·M·x + a1·K·x + B·x.
pub struct Soil<'a> {
    pub elements: &'a ElementMatrices,
    /// The masses M (the soil's and the bars') and the absorbing sides' dashpots B.
    pub inertia: &'a Inertia,
    /// Rayleigh's [a0, a1].
    pub rayleigh: [f64; 2],
}

impl Soil<'_> {
    /// M·(s·x + a0·w) + a1·K·w + B·w − c·r, in one pass over the elements.
    fn damped(&self, x: &[f64], s: f64, w: &[f64], c: f64, r: &[f64]) -> Vec<f64> {
        let Soil { elements, inertia, rayleigh } = *self;
        let inertial: Vec<f64> = x.iter().zip(w).map(|(x, w)| s * x + rayleigh[0] * w).collect();
        let mut f = inertia.damping_times(&elements.blocks, &inertial, rayleigh[1], w);
        if c != 0.0 {
            for (f, r) in f.iter_mut().zip(r) {
                *f -= c * r;
            }
        }
        f
    }
}

impl StepStart {
    /// The step from `motion` at displacements `u0`.
    pub fn new(soil: &Soil<'_>, u0: &[f64], motion: &Motion, k: &StepCoefficients) -> StepStart {
        let (v0, a0) = (&motion.velocity, &motion.acceleration);
        let p: Vec<f64> = (0..u0.len()).map(|i| -k.c0 * u0[i] - k.c2 * v0[i] - k.c3 * a0[i]).collect();
        let q: Vec<f64> = (0..u0.len()).map(|i| -k.c1 * u0[i] + k.c4 * v0[i] + k.c5 * a0[i]).collect();
        // h = M·p/(1 + α) + C·(q − α'·v₀) − α'·R(u₀), C = a0·M + a1·K + B
        let w: Vec<f64> = q.iter().zip(v0).map(|(q, v)| q - k.carried * v).collect();
        let constant = soil.damped(&p, k.inertia_weight, &w, k.carried, &motion.residual);
        StepStart { p, q, constant }
    }

    /// The motion at the step's end, time `time` and ground acceleration `ground`, from its
    /// displacements `u1` and the motion at its start.
    pub fn end(
        &self,
        soil: &Soil<'_>,
        u1: &[f64],
        start: &Motion,
        k: &StepCoefficients,
        time: f64,
        ground: [f64; 2],
    ) -> Motion {
        let acceleration: Vec<f64> = u1.iter().zip(&self.p).map(|(u, p)| k.c0 * u + p).collect();
        let velocity: Vec<f64> = u1.iter().zip(&self.q).map(|(u, q)| k.c1 * u + q).collect();
        // R(u₁) = −(M·a₁/(1 + α) + C·(v₁ − α'·v₀) − α'·R(u₀))
        let w: Vec<f64> = velocity.iter().zip(&start.velocity).map(|(v, v0)| v - k.carried * v0).collect();
        let dynamic = soil.damped(&acceleration, k.inertia_weight, &w, k.carried, &start.residual);
        let residual = dynamic.iter().map(|f| -f).collect();
        Motion { time, velocity, acceleration, ground, relative: start.relative, residual }
    }
}
