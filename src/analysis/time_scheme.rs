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

/// One step from `motion` (at displacements `u0`) under the coefficients `k`: what the step's end
/// follows from its displacements u₁, as a₁ = c0·u₁ + p and v₁ = c1·u₁ + q, and the constant force
/// h of the step's equation; with the images of p and q under M and C.
pub struct StepStart {
    p: Vec<f64>,
    q: Vec<f64>,
    /// M·p, M·q, C·p, C·q.
    mp: Vec<f64>,
    mq: Vec<f64>,
    cp: Vec<f64>,
    cq: Vec<f64>,
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
    /// Whether C = 0: no Rayleigh damping and no dashpots.
    fn undamped(&self) -> bool {
        self.rayleigh == [0.0, 0.0] && !self.inertia.has_dashpots()
    }

    /// M·x.
    fn mass_times(&self, x: &[f64]) -> Vec<f64> {
        self.inertia.mass_times(&self.elements.blocks, x)
    }

    /// C·x = a0·M·x + a1·K·x + B·x, in one pass over the elements.
    fn damping_times(&self, x: &[f64]) -> Vec<f64> {
        if self.undamped() {
            return vec![0.0; x.len()];
        }
        let scaled: Vec<f64> = x.iter().map(|x| self.rayleigh[0] * x).collect();
        self.inertia.damping_times(&self.elements.blocks, &scaled, self.rayleigh[1], x)
    }
}

/// M·x and C·x of a motion's displacements, velocities and accelerations, carried from step to
/// step with the motion: each is the image of the motion's own recurrence (a₁ = c0·u₁ + p gives
/// C·a₁ = c0·C·u₁ + C·p), so that a step makes C·u₁ and M·u₁ alone, and not the products of its
/// start's and its end's damping forces, each a pass over the elements.
#[derive(Debug, Clone)]
pub struct Products {
    mu: Vec<f64>,
    mv: Vec<f64>,
    ma: Vec<f64>,
    cu: Vec<f64>,
    cv: Vec<f64>,
    ca: Vec<f64>,
}

impl Products {
    /// Of a motion at rest at displacements `u`.
    pub fn at_rest(soil: &Soil<'_>, u: &[f64]) -> Products {
        let zero = vec![0.0; u.len()];
        Products {
            mu: soil.mass_times(u),
            mv: zero.clone(),
            ma: zero.clone(),
            cu: soil.damping_times(u),
            cv: zero.clone(),
            ca: zero,
        }
    }
}

/// c·x + y, term by term.
fn axpy(c: f64, x: &[f64], y: &[f64]) -> Vec<f64> {
    x.iter().zip(y).map(|(x, y)| c * x + y).collect()
}

/// c_u·u + c_v·v + c_a·a, term by term.
fn combine(c: [f64; 3], u: &[f64], v: &[f64], a: &[f64]) -> Vec<f64> {
    u.iter().zip(v).zip(a).map(|((u, v), a)| c[0] * u + c[1] * v + c[2] * a).collect()
}

impl StepStart {
    /// The step from `motion` at displacements `u0`, whose products are `at`.
    pub fn new(u0: &[f64], motion: &Motion, at: &Products, k: &StepCoefficients) -> StepStart {
        let (v0, a0) = (&motion.velocity, &motion.acceleration);
        let (to_p, to_q) = ([-k.c0, -k.c2, -k.c3], [-k.c1, k.c4, k.c5]);
        let (p, q) = (combine(to_p, u0, v0, a0), combine(to_q, u0, v0, a0));
        let (mp, mq) = (combine(to_p, &at.mu, &at.mv, &at.ma), combine(to_q, &at.mu, &at.mv, &at.ma));
        let (cp, cq) = (combine(to_p, &at.cu, &at.cv, &at.ca), combine(to_q, &at.cu, &at.cv, &at.ca));
        // h = M·p/(1 + α) + C·(q − α'·v₀) − α'·R(u₀)
        let constant = (0..u0.len())
            .map(|i| k.inertia_weight * mp[i] + cq[i] - k.carried * at.cv[i] - k.carried * motion.residual[i])
            .collect();
        StepStart { p, q, mp, mq, cp, cq, constant }
    }

    /// The motion at the step's end, time `time` and ground acceleration `ground`, and its
    /// products, from its displacements `u1`, the step's D·u₁ where the step's closing check found
    /// it (`operator`), and the motion at its start and its products `at`.
    #[allow(clippy::too_many_arguments)]
    pub fn end(
        &self,
        soil: &Soil<'_>,
        u1: &[f64],
        operator: Option<&[f64]>,
        start: &Motion,
        at: &Products,
        k: &StepCoefficients,
        time: f64,
        ground: [f64; 2],
    ) -> (Motion, Products) {
        // a₁ = c0·u₁ + p, v₁ = c1·u₁ + q, and their images under M and C alike
        let (acceleration, velocity) = (axpy(k.c0, u1, &self.p), axpy(k.c1, u1, &self.q));
        let mu = soil.mass_times(u1);
        // D = c0/(1 + α)·M + c1·C, so C·u₁ = (D·u₁ − c0/(1 + α)·M·u₁)/c1 from the check's D·u₁
        let cu = match operator {
            Some(d) if !soil.undamped() => {
                let m = k.c0 * k.inertia_weight;
                d.iter().zip(&mu).map(|(d, mu)| (d - m * mu) / k.c1).collect()
            }
            _ => soil.damping_times(u1),
        };
        let (ma, mv) = (axpy(k.c0, &mu, &self.mp), axpy(k.c1, &mu, &self.mq));
        let (ca, cv) = (axpy(k.c0, &cu, &self.cp), axpy(k.c1, &cu, &self.cq));
        // R(u₁) = −(M·a₁/(1 + α) + C·(v₁ − α'·v₀) − α'·R(u₀))
        let residual = (0..u1.len())
            .map(|i| -(k.inertia_weight * ma[i] + cv[i] - k.carried * at.cv[i] - k.carried * start.residual[i]))
            .collect();
        let motion = Motion { time, velocity, acceleration, ground, relative: start.relative, residual };
        (motion, Products { mu, mv, ma, cu, cv, ca })
    }
}
