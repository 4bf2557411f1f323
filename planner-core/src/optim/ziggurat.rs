//! The standard normal by Marsaglia and Tsang's ziggurat (2000), 128 layers, in `f32`.
//!
//! One 32-bit word per draw in 98.8% of draws: its low 7 bits pick a layer, bit 7 the sign,
//! and its high 24 bits the magnitude `j`; `j W[i]` is the draw when `j < K[i]` (the point
//! lies inside the curve). Otherwise the wedge test (one `open_unit` and one `expf`) or, in
//! the base layer, Marsaglia's tail method (`logf`s) decides, and a rejected point draws a
//! new word. The polar method it replaces cost a `logf`, a division and a square root per
//! pair, plus 27% rejected attempts: most of a TCLHHO plan's Levy steps on a Cortex-M4.
//! (The index and the magnitude come from separate bits: the original `rnor` took both from
//! the same word's low bits, which correlates them.)
//!
//! Layers: `f(x) = exp(-x^2 / 2)`, `R = 3.442619855899`, each layer of area
//! `V = 9.91256303526217e-3`; `x_0 = V / f(R)` (the base layer's equivalent width, its
//! strip plus the tail), `x_1 = R`, `x_{i+1} = sqrt(-2 ln(V / x_i + f(x_i)))`, `x_128 = 0`.
//! The tables below are those values rounded to `f32` (a test recomputes them in `f64`).

use super::random::Random;

/// The start of the tail.
const R: f32 = 3.442_619_8;

/// A standard normal draw.
#[inline]
pub(super) fn normal(rng: &mut Random) -> f32 {
    let (negative, x) = draw(rng);
    if negative { -x } else { x }
}

/// The magnitude of a standard normal draw: [`normal`] without its sign (the same words are
/// drawn, bit 7 of the accepted one is ignored), for a caller that only squares it.
#[inline]
pub(super) fn magnitude(rng: &mut Random) -> f32 {
    draw(rng).1
}

/// One draw: its sign (bit 7 of the accepted word) and its magnitude.
#[inline(always)]
fn draw(rng: &mut Random) -> (bool, f32) {
    loop {
        let u = rng.next_u32();
        let i = (u & 127) as usize;
        let j = u >> 8;
        let negative = u & 128 != 0;
        let (k, w) = LAYERS[i];
        let x = j as f32 * w;
        if j < k {
            return (negative, x);
        }
        let (next, v) = slow(rng.clone(), i, x);
        *rng = next;
        if let Some(v) = v {
            return (negative, v);
        }
    }
}

/// [`K`] and [`W`] side by side: one table address and one index for both lookups of a
/// draw (two addresses were rebuilt per draw in the Levy loop, short of registers).
static LAYERS: [(u32, f32); 128] = {
    let mut t = [(0, 0.0); 128];
    let mut i = 0;
    while i < 128 {
        t[i] = (K[i], W[i]);
        i += 1;
    }
    t
};

/// The draws outside the inner rectangles: the tail (layer 0) or a wedge; `None` rejects.
///
/// The generator goes in and out by value: were its address passed, a caller's local copy
/// of it could not live in registers in the loops that draw (three loads and two stores
/// per draw in the Levy steps on a Cortex-M4).
#[cold]
#[inline(never)]
fn slow(mut rng: Random, i: usize, x: f32) -> (Random, Option<f32>) {
    if i == 0 {
        // Marsaglia's tail: x = -ln(u1) / R, accepted when -2 ln(u2) > x^2.
        loop {
            let t = -libm::logf(rng.open_unit()) * (1.0 / R);
            let y = -libm::logf(rng.open_unit());
            if y + y > t * t {
                return (rng, Some(R + t));
            }
        }
    }
    let (f_out, f_in) = (F[i], F.get(i + 1).copied().unwrap_or(1.0));
    let y = f_out + rng.open_unit() * (f_in - f_out);
    (rng, (y < libm::expf(-0.5 * x * x)).then_some(x))
}

/// `x_i / 2^24`: layer `i` spans `[0, x_i]`; `x_0 = V / f(R)`, `x_1 = R`.
pub(super) const W: [f32; 128] = [
    2.2131718e-7,
    2.0519613e-7,
    1.9211083e-7,
    1.8377476e-7,
    1.7754414e-7,
    1.7251635e-7,
    1.6827138e-7,
    1.6457852e-7,
    1.6129694e-7,
    1.5833416e-7,
    1.5562607e-7,
    1.5312634e-7,
    1.5080033e-7,
    1.4862147e-7,
    1.4656891e-7,
    1.4462594e-7,
    1.4277902e-7,
    1.4101693e-7,
    1.3933034e-7,
    1.3771138e-7,
    1.3615335e-7,
    1.3465045e-7,
    1.3319769e-7,
    1.3179073e-7,
    1.3042572e-7,
    1.2909929e-7,
    1.2780846e-7,
    1.2655053e-7,
    1.2532313e-7,
    1.2412407e-7,
    1.229514e-7,
    1.2180338e-7,
    1.2067837e-7,
    1.1957489e-7,
    1.1849163e-7,
    1.17427305e-7,
    1.163808e-7,
    1.15351035e-7,
    1.1433705e-7,
    1.1333791e-7,
    1.12352794e-7,
    1.11380885e-7,
    1.10421446e-7,
    1.09473795e-7,
    1.0853726e-7,
    1.0761123e-7,
    1.0669511e-7,
    1.05788374e-7,
    1.0489048e-7,
    1.0400093e-7,
    1.0311926e-7,
    1.0224502e-7,
    1.01377765e-7,
    1.00517084e-7,
    9.9662586e-8,
    9.8813885e-8,
    9.797061e-8,
    9.7132414e-8,
    9.629894e-8,
    9.546986e-8,
    9.464484e-8,
    9.3823566e-8,
    9.300573e-8,
    9.219103e-8,
    9.137916e-8,
    9.056983e-8,
    8.976275e-8,
    8.8957634e-8,
    8.8154195e-8,
    8.7352156e-8,
    8.6551225e-8,
    8.575113e-8,
    8.4951594e-8,
    8.4152326e-8,
    8.335304e-8,
    8.255345e-8,
    8.1753264e-8,
    8.09522e-8,
    8.014993e-8,
    7.934618e-8,
    7.854061e-8,
    7.773291e-8,
    7.692275e-8,
    7.6109785e-8,
    7.5293656e-8,
    7.447401e-8,
    7.365045e-8,
    7.282259e-8,
    7.199e-8,
    7.115225e-8,
    7.0308886e-8,
    6.945942e-8,
    6.860333e-8,
    6.7740075e-8,
    6.686908e-8,
    6.598971e-8,
    6.510132e-8,
    6.420318e-8,
    6.329453e-8,
    6.2374525e-8,
    6.144227e-8,
    6.0496774e-8,
    5.9536948e-8,
    5.856161e-8,
    5.7569448e-8,
    5.6559003e-8,
    5.5528652e-8,
    5.4476573e-8,
    5.3400715e-8,
    5.2298752e-8,
    5.1168016e-8,
    5.000545e-8,
    4.8807497e-8,
    4.7569994e-8,
    4.628801e-8,
    4.495565e-8,
    4.3565745e-8,
    4.2109466e-8,
    4.057574e-8,
    3.895036e-8,
    3.7214672e-8,
    3.5343344e-8,
    3.3300648e-8,
    3.103352e-8,
    2.8457512e-8,
    2.542424e-8,
    2.1628823e-8,
    1.6231589e-8,
];

/// `floor(2^24 x_{i+1} / x_i)`: a 24-bit magnitude below it lands inside the curve.
pub(super) const K: [u32; 128] = [
    15555140, 15707337, 16049218, 16208407, 16302110, 16364393, 16409025, 16442689, 16469044,
    16490264, 16507732, 16522367, 16534808, 16545510, 16554811, 16562964, 16570162, 16576558,
    16582272, 16587401, 16592024, 16596205, 16599998, 16603448, 16606592, 16609464, 16612090,
    16614493, 16616695, 16618713, 16620562, 16622256, 16623807, 16625225, 16626519, 16627697,
    16628767, 16629736, 16630608, 16631389, 16632084, 16632697, 16633230, 16633688, 16634074,
    16634389, 16634636, 16634816, 16634933, 16634986, 16634978, 16634909, 16634780, 16634592,
    16634345, 16634040, 16633676, 16633253, 16632772, 16632232, 16631633, 16630973, 16630252,
    16629469, 16628623, 16627712, 16626734, 16625689, 16624574, 16623386, 16622124, 16620785,
    16619366, 16617864, 16616275, 16614596, 16612821, 16610948, 16608971, 16606884, 16604681,
    16602357, 16599904, 16597313, 16594578, 16591687, 16588632, 16585400, 16581979, 16578356,
    16574514, 16570436, 16566103, 16561495, 16556586, 16551350, 16545757, 16539771, 16533355,
    16526461, 16519041, 16511033, 16502371, 16492973, 16482746, 16471580, 16459345, 16445882,
    16431004, 16414481, 16396028, 16375293, 16351833, 16325080, 16294297, 16258510, 16216401,
    16166149, 16105157, 16029596, 15933579, 15807563, 15635011, 15384586, 14988941, 14272655,
    12590646, 0,
];

/// `f(x_i) = exp(-x_i^2 / 2)`, `x_128 = 0`.
pub(super) const F: [f32; 129] = [
    1.0143525e-3,
    2.6696292e-3,
    5.548995e-3,
    8.624485e-3,
    1.1839478e-2,
    1.5167298e-2,
    1.8592102e-2,
    2.2103304e-2,
    2.5693292e-2,
    2.9356318e-2,
    3.3087887e-2,
    3.688439e-2,
    4.0742867e-2,
    4.4660863e-2,
    4.8636295e-2,
    5.26674e-2,
    5.6752663e-2,
    6.089077e-2,
    6.508058e-2,
    6.932112e-2,
    7.3611505e-2,
    7.7950984e-2,
    8.23389e-2,
    8.677467e-2,
    9.12578e-2,
    9.5787846e-2,
    1.0036444e-1,
    1.04987256e-1,
    1.0965602e-1,
    1.1437051e-1,
    1.19130544e-1,
    1.2393598e-1,
    1.2878671e-1,
    1.3368265e-1,
    1.3862377e-1,
    1.4361008e-1,
    1.4864157e-1,
    1.5371831e-1,
    1.5884037e-1,
    1.6400786e-1,
    1.692209e-1,
    1.7447963e-1,
    1.7978427e-1,
    1.8513499e-1,
    1.9053204e-1,
    1.9597565e-1,
    2.0146611e-1,
    2.0700371e-1,
    2.1258877e-1,
    2.1822165e-1,
    2.239027e-1,
    2.2963232e-1,
    2.3541094e-1,
    2.41239e-1,
    2.4711695e-1,
    2.530453e-1,
    2.5902456e-1,
    2.650553e-1,
    2.7113807e-1,
    2.772735e-1,
    2.834622e-1,
    2.8970486e-1,
    2.9600215e-1,
    3.0235484e-1,
    3.0876362e-1,
    3.152294e-1,
    3.217529e-1,
    3.283351e-1,
    3.3497685e-1,
    3.4167916e-1,
    3.4844297e-1,
    3.5526937e-1,
    3.621595e-1,
    3.6911446e-1,
    3.7613547e-1,
    3.832238e-1,
    3.903808e-1,
    3.9760786e-1,
    4.0490642e-1,
    4.1227803e-1,
    4.1972435e-1,
    4.27247e-1,
    4.3484783e-1,
    4.4252872e-1,
    4.5029163e-1,
    4.581387e-1,
    4.6607214e-1,
    4.740943e-1,
    4.8220766e-1,
    4.9041483e-1,
    4.9871865e-1,
    5.0712204e-1,
    5.156282e-1,
    5.2424055e-1,
    5.329627e-1,
    5.4179835e-1,
    5.507518e-1,
    5.598274e-1,
    5.6903e-1,
    5.783647e-1,
    5.8783704e-1,
    5.974532e-1,
    6.072195e-1,
    6.171434e-1,
    6.272325e-1,
    6.3749546e-1,
    6.479418e-1,
    6.58582e-1,
    6.694277e-1,
    6.8049186e-1,
    6.9178915e-1,
    7.033361e-1,
    7.151515e-1,
    7.272569e-1,
    7.3967725e-1,
    7.524416e-1,
    7.655842e-1,
    7.791461e-1,
    7.93177e-1,
    8.077383e-1,
    8.229072e-1,
    8.387836e-1,
    8.555006e-1,
    8.7324303e-1,
    8.9228165e-1,
    9.130436e-1,
    9.362827e-1,
    9.635997e-1,
    1.0,
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The tables are the layer edges of the module doc, rounded to `f32`.
    #[test]
    fn tables_follow_the_recurrence() {
        let (r, v) = (3.442619855899f64, 9.91256303526217e-3f64);
        let f = |x: f64| libm::exp(-0.5 * x * x);
        let mut x = [0.0f64; 129];
        x[0] = v / f(r);
        x[1] = r;
        for i in 1..128 {
            x[i + 1] = libm::sqrt(-2.0 * libm::log(v / x[i] + f(x[i])));
        }
        assert!(x[128] < 1e-4, "the layers close at 0: {}", x[128]);
        x[128] = 0.0;
        let scale = 16_777_216.0;
        for i in 0..128 {
            assert_eq!(W[i], (x[i] / scale) as f32, "W[{i}]");
            assert_eq!(
                u64::from(K[i]),
                libm::floor(x[i + 1] / x[i] * scale) as u64,
                "K[{i}]"
            );
        }
        for i in 0..129 {
            assert_eq!(F[i], f(x[i]) as f32, "F[{i}]");
        }
        assert_eq!(R, r as f32);
    }

    /// The draws follow the standard normal CDF: the Kolmogorov-Smirnov distance of 200,000
    /// draws, and the tail beyond R (layer 0's slow path), both within sampling error.
    #[test]
    fn draws_are_standard_normal() {
        let mut rng = Random::new(3);
        let n = 200_000;
        let mut v: std::vec::Vec<f64> = (0..n).map(|_| f64::from(normal(&mut rng))).collect();
        v.sort_unstable_by(f64::total_cmp);
        let cdf = |x: f64| 0.5 * libm::erfc(-x / core::f64::consts::SQRT_2);
        let d = v
            .iter()
            .enumerate()
            .map(|(k, &x)| {
                let c = cdf(x);
                (c - k as f64 / f64::from(n))
                    .abs()
                    .max((c - (k + 1) as f64 / f64::from(n)).abs())
            })
            .fold(0.0, f64::max);
        // The 0.1% critical value is 1.95 / sqrt(n) = 0.0044.
        assert!(d < 0.0044, "KS distance {d}");
        let tail = v.iter().filter(|x| x.abs() > f64::from(R)).count() as f64 / f64::from(n);
        let want = libm::erfc(f64::from(R) / core::f64::consts::SQRT_2);
        // 5.8e-4 expected, 116 draws: three standard errors are 32 draws.
        assert!((tail - want).abs() < 1.6e-4, "tail {tail} vs {want}");
    }
}
