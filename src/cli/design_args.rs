//! Value types of `ncgear design`'s flags, and the `X,Y` pair parser the commands share.

/// `--tooth-policy` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum ToothPolicyArg {
    /// Design for the module: the tooth count a constraint of the fit.
    Design,
    /// Scale the centre distance up to z = ⌈L/πm⌉ (tip moves radially by (s − 1)·l1).
    ScaleUp,
    /// Scale the centre distance to z = round(L/πm).
    Nearest,
    /// Scale the centre distance down to z = ⌊L/πm⌋.
    ScaleDown,
    /// Keep the centre distance; rescale the ratio amplitude so that L = zπm.
    RatioAmplitude,
    /// Keep the gears; use the non-standard module L/(zπ), z = round(L/πm).
    AdjustModule,
}

/// `--sense` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SenseArg {
    /// Either; the better-realisable law when both trace the path.
    Auto,
    /// Counter-clockwise.
    Ccw,
    /// Clockwise.
    Cw,
}

/// `--limits` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LimitsArg {
    /// Design within the gear limits.
    On,
    /// The ratio bounds alone.
    Off,
}

/// `--refine` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum RefineArg {
    /// When the patent route misses the tolerance.
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

/// `--route` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum RouteArg {
    /// Front half exact.
    Ac,
    /// Back half exact.
    Bd,
}

/// Parses `X,Y`.
pub fn parse_pair(s: &str) -> Result<[f64; 2], String> {
    let v: Vec<&str> = s.split(',').map(str::trim).collect();
    let num = |t: &str| t.parse::<f64>().ok().filter(|x| x.is_finite());
    match v.as_slice() {
        [a, b] => match (num(a), num(b)) {
            (Some(x), Some(y)) => Ok([x, y]),
            _ => Err(format!("`{s}`: expected two finite numbers `X,Y`")),
        },
        _ => Err(format!(
            "`{s}`: expected two numbers separated by a comma, e.g. `0,0`"
        )),
    }
}
