"""C99 export with int8 weights (see `anytip.deploy.quantize`): same header and signature as the
float32 export, `void anytip_infer(const float *in, float *out)`, pressures in Pa, outputs in N and rad.

Weights are int8, four to a 32-bit word (two inputs x two outputs) so that a Cortex-M4 does two
MACs per SMLAD instruction (ACLE intrinsics; portable C elsewhere); activations are int16, sums
int32, then one float32 multiply-add per output channel. Static buffers only, no heap, no libm.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from anytip.deploy.c_export import HEADER, SOURCE, c_floats, render_header
from anytip.deploy.net import DeployNet
from anytip.deploy.quantize import QuantNet

KERNEL_Q = """
#if defined(__ARM_FEATURE_SIMD32) && __ARM_FEATURE_SIMD32
#include <arm_acle.h>
#define SXTB16(w) ((uint32_t)__sxtb16(w))
#define SMLAD(x, w, a) __smlad(x, w, a)
static uint32_t SXTB16_ROR8(uint32_t w)
{
    uint32_t r;
    __asm__("sxtb16 %0, %1, ror #8" : "=r"(r) : "r"(w));
    return r;
}
#else
/* The same arithmetic in portable C for other targets. */
static uint32_t SXTB16(uint32_t w)
{
    return (uint32_t)(uint16_t)(int16_t)(int8_t)(w & 0xffu)
        | ((uint32_t)(uint16_t)(int16_t)(int8_t)((w >> 16) & 0xffu) << 16);
}
static int32_t SMLAD(uint32_t x, uint32_t w, int32_t a)
{
    return a + (int16_t)(x & 0xffffu) * (int16_t)(w & 0xffffu) + (int16_t)(x >> 16) * (int16_t)(w >> 16);
}
#define SXTB16_ROR8(w) SXTB16((w) >> 8)
#endif

static int16_t sat16(float v)
{
    v = v >= 0.0f ? v + 0.5f : v - 0.5f;
    if (v > 32767.0f) return 32767;
    if (v < -32767.0f) return -32767;
    return (int16_t)v;
}

/* Two int16 activations x[i], x[i + 1] as one word (low half first). */
static uint32_t pair(const int16_t *x)
{
    uint32_t v;
    memcpy(&v, x, sizeof v);
    return v;
}

/* acc[o] = sum_i x[i] w[i][o] (int32). A weight word holds w[i][o], w[i][o+1], w[i+1][o], w[i+1][o+1]
 * (int8, low byte first); words come in output blocks of 4, then 2 (see pack_pairs). n_in, n_out even. */
static void dense_q(const int16_t *x, const uint32_t *w, int32_t *acc, int n_in, int n_out)
{
    int o = 0, i;
    for (; o + 4 <= n_out; o += 4) {
        int32_t a0 = 0, a1 = 0, a2 = 0, a3 = 0;
        for (i = 0; i < n_in; i += 2, w += 2) {
            const uint32_t v = pair(x + i);
            a0 = SMLAD(v, SXTB16(w[0]), a0); a1 = SMLAD(v, SXTB16_ROR8((w[0])), a1);
            a2 = SMLAD(v, SXTB16(w[1]), a2); a3 = SMLAD(v, SXTB16_ROR8((w[1])), a3);
        }
        acc[o] = a0; acc[o + 1] = a1; acc[o + 2] = a2; acc[o + 3] = a3;
    }
    for (; o + 2 <= n_out; o += 2) {
        int32_t a0 = 0, a1 = 0;
        for (i = 0; i < n_in; i += 2, w++) {
            const uint32_t v = pair(x + i);
            a0 = SMLAD(v, SXTB16(w[0]), a0); a1 = SMLAD(v, SXTB16_ROR8((w[0])), a1);
        }
        acc[o] = a0; acc[o + 1] = a1;
    }
}

/* y = round(relu(acc * mult + bias)) as int16 for the next layer. */
static void requant(const int32_t *acc, const float *mult, const float *bias, int16_t *y, int n)
{
    for (int o = 0; o < n; o++) {
        const float v = (float)acc[o] * mult[o] + bias[o];
        y[o] = sat16(v > 0.0f ? v : 0.0f);
    }
}
"""


def _even(n: int) -> int:
    return n + (n % 2)


def pack_pairs(q_w: np.ndarray) -> np.ndarray:
    """int8 q_w (in, out) -> uint32 words for dense_q: in and out padded to even with zeros, output
    blocks of 4, then 2; in a block, input pairs in order, each pair as words over output pairs."""
    n_in, n_out = q_w.shape
    w = np.zeros((_even(n_in), _even(n_out)), np.int8)
    w[:n_in, :n_out] = q_w
    words, o = [], 0
    for size in (4, 2):
        while o + size <= w.shape[1]:
            blk = w[:, o:o + size].reshape(-1, 2, size // 2, 2)  # (pair, i in pair, out pair, o in pair)
            quads = np.ascontiguousarray(blk.transpose(0, 2, 1, 3)).reshape(-1, 4)
            words.append(quads.view("<u4").reshape(-1))
            o += size
    return np.concatenate(words)


def c_hex(words: np.ndarray, per_line: int = 8) -> str:
    vals = [f"0x{int(v):08x}u" for v in words]
    return ",\n".join("    " + ", ".join(vals[i:i + per_line]) for i in range(0, len(vals), per_line))


def _tables(q: QuantNet) -> str:
    out = [f"static const float IN_MEAN[{q.in_mean.size}] = {{\n{c_floats(q.in_mean)}\n}};",
           f"static const float IN_INV_SCALE[{q.in_inv_scale.size}] = {{\n{c_floats(q.in_inv_scale)}\n}};",
           f"static const float OUT_OFFSET[{q.out_offset.size}] = {{\n{c_floats(q.out_offset)}\n}};"]
    for k, L in enumerate(q.layers):
        words = pack_pairs(L.q_w)
        out.append(f"static const uint32_t W{k}[{words.size}] = {{ /* int8 x4 */\n{c_hex(words)}\n}};")
        out.append(f"static const float M{k}[{L.mult.size}] = {{\n{c_floats(L.mult)}\n}};")
        out.append(f"static const float B{k}[{L.bias.size}] = {{\n{c_floats(L.bias)}\n}};")
    return "\n".join(out)


def _body(q: QuantNet) -> str:
    n_in = q.layers[0].q_w.shape[0]
    lines = [f"    for (int i = 0; i < {n_in}; i++)\n"
             "        act_a[i] = sat16((in[i] - IN_MEAN[i]) * IN_INV_SCALE[i]);"]
    if len(q.layers) == 1:
        lines.append("    (void)requant; (void)act_b;")
    src, dst = "act_a", "act_b"
    last = len(q.layers) - 1
    for k, L in enumerate(q.layers):
        n_i, n_o = L.q_w.shape
        lines.append(f"    dense_q({src}, W{k}, acc, {_even(n_i)}, {_even(n_o)});")
        if k < last:
            lines.append(f"    requant(acc, M{k}, B{k}, {dst}, {n_o});")
            src, dst = dst, src
        else:
            relu = "v = v > 0.0f ? v : 0.0f; " if L.relu else ""
            lines.append(f"    for (int o = 0; o < {n_o}; o++) {{\n"
                         f"        float v = (float)acc[o] * M{k}[o] + B{k}[o]; "
                         f"{relu}out[o] = v + OUT_OFFSET[o]; }}")
    return "\n".join(lines)


def render_source_int8(q: QuantNet, net: DeployNet) -> str:
    width = _even(max(max(L.q_w.shape) for L in q.layers))
    return f"""/* anytip contact model, unit {net.unit}: int8 weights, int16 activations, int32 sums.
 * Generated by `anytip export`. */
/* Each requantisation rounds its product before adding the bias, as the verified model does:
 * a fused multiply-add (Cortex-M4F builds contract by default) can move an int16 activation
 * by one step. */
#pragma GCC optimize ("fp-contract=off")
#include <stdint.h>
#include <string.h>
#include "{HEADER}"

{_tables(q)}

static int16_t act_a[{width}], act_b[{width}];
static int32_t acc[{width}];
{KERNEL_Q}
void anytip_infer(const float *in, float *out)
{{
{_body(q)}
}}
"""


def write_c_int8(q: QuantNet, net: DeployNet, out_dir: str | Path) -> tuple[Path, Path]:
    """Write the int8 header and source into out_dir; returns (header, source)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    h, c = out_dir / HEADER, out_dir / SOURCE
    h.write_text(render_header(net, "int8"))
    c.write_text(render_source_int8(q, net))
    return h, c
