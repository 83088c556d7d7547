//! `geoslip bench`: the solver and nonlinear benchmarks, each size measured in a child process of
//! its own (`geoslip bench-one`), printed as a Markdown table.

use crate::linsol::{Backend, Ordering};

/// The nonlinear benchmark: each size in a child process of its own, one Markdown table.
pub fn bench_nonlinear(sizes: &[usize], backends: &[Backend], orderings: &[Ordering]) -> Result<(), String> {
    use super::measure::NonlinearMeasurement;
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let backend = backends.first().copied().unwrap_or(Backend::Auto).resolve();
    crate::linsol::check_available(backend).map_err(|e| e.to_string())?;
    let ordering = orderings.first().copied().unwrap_or(Ordering::Auto);
    println!(
        "geoslip {} — nonlinear benchmark on {} ({} ordering): multi-layer pull-out box, 20 pull increments",
        env!("CARGO_PKG_VERSION"),
        backend.name(),
        ordering.name()
    );
    println!();
    println!("| unknowns | layers | stations | increments | iterations | analyses | factorisations | re-associations | slip / element | wall [s] | per increment [s] | per iteration [s] | setup | assembly | interface | residual | solution check | analysis | factorisation | solve | output | run / MUMPS | iteration / (factorisation + solve) | peak [MB] | peak [KB/unknown] | peak / (INFOG(22) + model) |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &size in sizes {
        let out = std::process::Command::new(&exe)
            .args(["bench-one", "--nonlinear", "--dofs", &size.to_string(), "--backend", backend.name()])
            .args(["--ordering", ordering.name()])
            .output()
            .map_err(|e| e.to_string())?;
        let m: NonlinearMeasurement = match serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()) {
            Ok(m) => m,
            Err(_) => {
                let why = String::from_utf8_lossy(&out.stderr);
                println!("| {size} | failed: {} |", why.lines().last().unwrap_or("no output (killed?)"));
                continue;
            }
        };
        if let Some(e) = &m.error {
            println!("| {} | failed after {} increments: {e} |", m.dofs, m.increments);
            continue;
        }
        let share = |s: f64| format!("{:.0} %", 100.0 * s / m.total_seconds);
        let mumps = m.analyse_seconds + m.factorize_seconds + m.solve_seconds;
        let in_run = m.total_seconds - m.output_seconds - m.setup_seconds;
        let memory_ratio = m.factor_memory_mb.map(|f| format!("{:.2}", m.peak_memory_mb / (f + m.model_memory_mb)));
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.1} | {:.1} | {:.3} | {:.4} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.0} | {:.2} | {} |",
            m.dofs,
            m.layers,
            m.stations,
            m.increments,
            m.iterations,
            m.analyses,
            m.factorizations,
            m.reassociations,
            m.max_slip / m.element_length,
            m.total_seconds,
            m.total_seconds / m.increments.max(1) as f64,
            in_run / m.iterations.max(1) as f64,
            share(m.setup_seconds),
            share(m.assembly_seconds),
            share(m.interface_seconds),
            share(m.residual_seconds),
            share(m.check_seconds),
            share(m.analyse_seconds),
            share(m.factorize_seconds),
            share(m.solve_seconds),
            share(m.output_seconds),
            in_run / mumps,
            // the target's reading: a mean iteration against one factorisation and one solve
            (in_run / m.iterations.max(1) as f64)
                / (m.factorize_seconds / m.factorizations.max(1) as f64 + m.solve_seconds / m.solves.max(1) as f64),
            m.peak_memory_mb,
            1024.0 * m.peak_memory_mb / m.dofs as f64,
            memory_ratio.unwrap_or_else(|| "n/a".into())
        );
    }
    Ok(())
}

/// Run every (size, backend) measurement in a child process and print a Markdown table.
pub fn bench(sizes: &[usize], backends: &[Backend], repeats: usize, orderings: &[Ordering]) -> Result<(), String> {
    use super::measure::Measurement;
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let backends: Vec<Backend> =
        if backends.is_empty() { Backend::available() } else { backends.iter().map(|b| b.resolve()).collect() };
    for b in &backends {
        crate::linsol::check_available(*b).map_err(|e| e.to_string())?;
    }
    println!("geoslip {} — backends: {}", env!("CARGO_PKG_VERSION"), env!("GEOSLIP_BACKENDS"));
    println!();
    println!("| unknowns | nonzeros | backend | analysis [s] | factorisation [s] | solve [s] | factor entries | peak memory [MB] | ‖Ax−b‖/‖b‖ |");
    println!("|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    // MUMPS once per ordering asked for; the other backends once
    let orderings: Vec<Ordering> = if orderings.is_empty() { vec![Ordering::Auto] } else { orderings.to_vec() };
    for &size in sizes {
        let mut runs: Vec<(String, Ordering)> = vec![("none".into(), Ordering::Auto)];
        for &b in &backends {
            if b == Backend::Mumps {
                runs.extend(orderings.iter().map(|&o| (b.name().to_string(), o)));
            } else {
                runs.push((b.name().to_string(), Ordering::Auto));
            }
        }
        for (name, ordering) in runs {
            if name == "dense" && size > crate::linsol::dense_ref::SIZE_LIMIT {
                continue;
            }
            let out = std::process::Command::new(&exe)
                .args(["bench-one", "--dofs", &size.to_string(), "--backend", &name, "--ordering", ordering.name()])
                .output()
                .map_err(|e| e.to_string())?;
            let line = String::from_utf8_lossy(&out.stdout);
            let m: Measurement = match serde_json::from_str(line.trim()) {
                Ok(m) => m,
                Err(_) => {
                    println!(
                        "| {size} | | {name} | failed: {} | | | | | |",
                        String::from_utf8_lossy(&out.stderr).lines().last().unwrap_or("no output")
                    );
                    continue;
                }
            };
            if let Some(e) = &m.error {
                println!("| {} | {} | {} | failed: {e} | | | | | |", m.unknowns, m.nonzeros, m.backend);
                continue;
            }
            if name == "none" {
                println!(
                    "| {} | {} | (model and assembly only) | | | | | {:.0} | |",
                    m.unknowns, m.nonzeros, m.peak_memory_mb
                );
                continue;
            }
            println!(
                "| {} | {} | {} | {:.3} | {:.3} | {:.4} | {} | {:.0} | {:.1e} |",
                m.unknowns,
                m.nonzeros,
                m.backend,
                m.analyse_seconds,
                m.factorize_seconds,
                m.solve_seconds,
                m.factor_entries.map(|e| e.to_string()).unwrap_or_else(|| "n/a".into()),
                m.peak_memory_mb,
                m.relative_residual
            );
        }
    }
    if backends.contains(&Backend::Mumps) {
        println!();
        println!("MUMPS path (geoslip's wrapper from the assembled matrix: JOB −1, lower triangle and 1-based indices, JOB 1, 2, 3,");
        println!("residual check, JOB −2) against a bare MUMPS call");
        println!("(JOB −1, 1, 2, 3, −2 on ready-made coordinates), interleaved, median of {repeats}:");
        println!();
        println!("| unknowns | path [s] | bare [s] | path / bare |");
        println!("|---:|---:|---:|---:|");
        for &size in sizes {
            let (path, bare, n) = super::measure::mumps_overhead(size, repeats.max(1))?;
            println!("| {n} | {path:.4} | {bare:.4} | {:.3} |", path / bare);
        }
    }
    Ok(())
}
