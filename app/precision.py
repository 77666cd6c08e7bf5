"""The precision test (paper section 4.3, Fig. 10): the texture-coordinate precision needed to
avoid magnification aliases.

    python -m app.precision --size 512          (make precision; PRECISION_SIZE=)

The scene scenes/fig10/precision.toml (coarsely triangulated objects seen close, so the texture
is magnified; not one of the paper's eight scenes of model.scene.passes.SCENES) is rendered by
the golden model for every configuration at every s_frac in --fracs (default 6..16 fraction
bits of the texture coordinates s, t, r), and compared with the float reference of the texture
as that configuration computes it (model.scene.passes.configured_texture: its approximations
made, so the difference is the arithmetic error alone): PSNR over the textured pixels. A
variant keeps the configuration's integer bits of s (s_w - s_frac, the range of s) and its
noise-space fraction p_frac where it can (p_frac <= s_frac + t_frac: lowered to s_frac + t_frac
where not); every other key is the configuration's. The smallest s_frac whose PSNR, and that
of every larger s_frac, is at least --db (40 dB) is that configuration's threshold.

Writes out/precision/ (staged: images <config>/s<k>.png, reference.png, report.json),
docs/precision.md, docs/images/precision.png (contact sheet: a crop at 1:1 of the reference and
of each s_frac) and docs/images/precision_psnr.png (PSNR against s_frac, matplotlib). With
--out, the docs go to <out>/docs.
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from model import reference
from model.hw import golden
from model.hw.config import CONFIG_NAMES, ROOT, doc_stamp, ConfigError, load_config, variant
from model.hw.quantize import FormatError
from model.imageio import compare, contact_sheet, write_image
from app.common import git_describe
from model.cli import Parser, UserError, check_config, check_range, progress_bar, resolve_scene, run_main, staged
from model.scene.passes import composite, configured_texture, frame_size, prepare_passes, to8

SCENE = ROOT / "scenes" / "fig10" / "precision.toml"
FRACS = tuple(range(6, 17))
DB = 40.0


def precision_variant(cfg, k: int):
    """cfg with k fraction bits of s: the same integer bits (s_w - s_frac), p_frac lowered to
    k + t_frac where it must be (p_frac <= s_frac + t_frac), and, where the golden model's int64 would
    overflow (the quadric's s x v product at full's q s28.20 and s_frac 16), q_frac lowered one bit at a
    time with q's integer bits kept (the row reports the q it took); ConfigError if no valid variant."""
    kw = {"s_frac": k, "s_w": k + cfg.s_w - cfg.s_frac, "p_frac": min(cfg.p_frac, k + cfg.t_frac)}
    err = None
    for dq in range(cfg.q_frac + 1):  # dq = 0: q as the file has it
        try:
            return variant(cfg, f"{cfg.name}-s{k}", **kw, q_frac=cfg.q_frac - dq, q_w=cfg.q_w - dq)
        except ConfigError as e:
            if "formats too wide" not in str(e):
                raise
            err = err or e
    raise err


def _images(cfg, passes, bg, W, H):
    """(golden image, textured mask) of the passes under cfg; FormatError if a value does not fit."""
    pds = prepare_passes(cfg, passes)
    layers, textured = [], np.zeros((H, W), bool)
    for pd in pds:
        layers.append((pd.mask, golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)))
        textured |= pd.mask
    return composite(layers, (H, W), bg), textured


def threshold(psnrs: dict, db: float = DB):
    """The smallest k such that psnrs[j] >= db for every j >= k (None: not reached)."""
    best = None
    for k in sorted(psnrs, reverse=True):
        if psnrs[k] is None or psnrs[k] < db:
            break
        best = k
    return best


PLATEAU_DB = 1.0


def plateau(psnrs: dict, within: float = PLATEAU_DB):
    """The smallest k from which every PSNR is within `within` dB of the highest s_frac's: where
    s_frac stops mattering against the configuration's other formats (None: no PSNR)."""
    top = psnrs.get(max(psnrs)) if psnrs else None
    return None if top is None else threshold(psnrs, top - within)


def run(size: int = 512, configs=CONFIG_NAMES, fracs=FRACS, scene_arg: str = str(SCENE), db: float = DB,
        out_root: Path | None = None, progress: bool = True) -> dict:
    from model.scene.frontend import render_passes
    from model.scene.scene import load_scene

    t0 = time.perf_counter()
    check_range("--size", size, 8, 1024)
    for c in configs:
        check_config(c)
    for k in fracs:
        check_range("--fracs", k, 1, 23, "fraction bits of s")
    name, path = resolve_scene(scene_arg)
    target = Path(out_root or ROOT / "out") / "precision"
    docs = ROOT / "docs" if out_root is None else Path(out_root) / "docs"
    command = f"make precision PRECISION_SIZE={size}"
    with staged(target, command) as out:
        scene = load_scene(path)
        W, H = frame_size(scene, size)
        passes = render_passes(scene, W, H)
        bar = progress_bar(progress, total=len(configs) * (len(fracs) + 1), desc=f"precision {W}x{H}")
        rep = {"status": "ok", "scene": name, "scene_file": str(path.relative_to(ROOT) if path.is_relative_to(ROOT)
                                                                   else path),
               "width": W, "height": H, "db": db, "fracs": list(fracs), "git": git_describe(), "command": command,
               "configs": {}}
        images = {}
        for c in configs:
            cfg = load_config(c)
            layers = [(ps.mask, reference.shade(configured_texture(cfg, ps.texture), ps.s[ps.mask], ps.J[ps.mask],
                                                cfg.perm, cfg.hash_bits)) for ps in passes]
            ref = composite(layers, (H, W), scene.background)
            write_image(out / c / "reference.png", to8(ref))
            images[(c, "reference")] = to8(ref)
            bar.update()
            rows = {}
            for k in fracs:
                row = {"s_frac": k}
                try:
                    v = precision_variant(cfg, k)
                    row.update(s_w=v.s_w, p_frac=v.p_frac)
                    if v.q_frac != cfg.q_frac:
                        row.update(q=f"s{v.q_w}.{v.q_frac}")
                    img, textured = _images(v, passes, scene.background, W, H)
                except (ConfigError, FormatError) as e:
                    row.update(psnr_db=None, error=" ".join(str(e).split()))
                else:
                    cmp = compare(img[textured], ref[textured])
                    row.update(psnr_db=cmp["psnr_db"], max_abs_error_lsb=round(cmp["max_abs_error_lsb"], 3),
                               mean_abs_error_lsb=round(cmp["mean_abs_error_lsb"], 4))
                    write_image(out / c / f"s{k}.png", to8(img))
                    images[(c, k)] = to8(img)
                rows[k] = row
                bar.update()
            psnrs = {k: r["psnr_db"] for k, r in rows.items()}
            rep["configs"][c] = {"s_frac": cfg.s_frac, "s_w": cfg.s_w, "p_frac": cfg.p_frac, "t_frac": cfg.t_frac,
                                 "rows": list(rows.values()), "threshold_s_frac": threshold(psnrs, db),
                                 "plateau_s_frac": plateau(psnrs),
                                 "psnr_at_own_s_frac_db": (psnrs.get(cfg.s_frac) if cfg.s_frac in psnrs
                                                           else _own_psnr(cfg, passes, scene.background, W, H, ref))}
        bar.close()
        rep["seconds"] = round(time.perf_counter() - t0, 2)
        (out / "report.json").write_text(json.dumps(rep, indent=2) + "\n")
    write_docs(rep, images, docs)
    return rep


def _own_psnr(cfg, passes, bg, W, H, ref):
    img, textured = _images(cfg, passes, bg, W, H)
    return compare(img[textured], ref[textured])["psnr_db"]


def _crop(img: np.ndarray, W: int, H: int, tile: int) -> np.ndarray:
    """A tile x tile crop at 1:1 around (0.55 W, 0.45 H) (the teapot's body, where the rings are
    magnified), or the whole image when it is smaller."""
    if W <= tile or H <= tile:
        return img
    x0 = min(max(int(0.55 * W) - tile // 2, 0), W - tile)
    y0 = min(max(int(0.45 * H) - tile // 2, 0), H - tile)
    return img[y0:y0 + tile, x0:x0 + tile]


def write_docs(rep: dict, images: dict, docs: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    W, H, fracs, db = rep["width"], rep["height"], rep["fracs"], rep["db"]
    tile = 128
    rows = []
    for c in rep["configs"]:
        row = [(f"{c}: float", _crop(images[(c, "reference")], W, H, tile))]
        row += [(f"s_frac {k}", _crop(images[(c, k)], W, H, tile) if (c, k) in images else None) for k in fracs]
        rows.append(row)
    (docs / "images").mkdir(parents=True, exist_ok=True)
    contact_sheet(docs / "images" / "precision.png", rows, tile=tile,
                  title=f"make precision: {rep['scene']} at {W}x{H}, {tile}x{tile} crops at 1:1, golden model by s_frac")
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    for c, r in rep["configs"].items():
        ks = [x["s_frac"] for x in r["rows"] if x["psnr_db"] is not None]
        ax.plot(ks, [x["psnr_db"] for x in r["rows"] if x["psnr_db"] is not None], marker="o", label=c)
    ax.axhline(db, color="grey", linestyle="--", linewidth=1, label=f"{db:g} dB")
    ax.set_xlabel("s_frac (fraction bits of the texture coordinates)")
    ax.set_ylabel("PSNR against the float reference (dB)")
    ax.set_title(f"Precision test (Fig. 10): {rep['scene']}, {W}x{H}")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    tmp = docs / "images" / ".precision_psnr.tmp.png"
    fig.savefig(tmp)
    plt.close(fig)
    tmp.replace(docs / "images" / "precision_psnr.png")

    L = ["# The precision test (paper section 4.3, Fig. 10)", "",
         f"Written by `{rep['command']}` ({rep['seconds']} s; git {rep['git']}; app/precision.py). "
         f"The scene `{rep['scene_file']}`: the Newell teapot at 2 x 2 quads a patch (256 triangles) in the "
         "wood of Fig. 1 and an icosahedron (20 triangles) in two-term marble, seen close, so the texture is "
         "magnified: a step of the texture coordinates' last bit spans pixels. Each configuration's golden model "
         f"renders it at s_frac = {fracs[0]}..{fracs[-1]} fraction bits of s, t, r, keeping the configuration's "
         "integer bits (s_w - s_frac) and every other key (p_frac, the noise-space fraction, lowered to "
         "s_frac + t_frac where it would exceed it, the one constraint s_frac enters); the PSNR is over the "
         f"{W}x{H} frame's textured pixels against the float reference of the texture as the configuration "
         "computes it (its noise terms, blend and gradient), so it measures the arithmetic alone, "
         "s_frac's share of it shrinking as s_frac grows until the configuration's other formats dominate.", "",
         "![PSNR against s_frac](images/precision_psnr.png)", "",
         "![contact sheet](images/precision.png)", "",
         "| s_frac | " + " | ".join(rep["configs"]) + " |", "|---" * (len(rep["configs"]) + 1) + "|"]
    for i, k in enumerate(fracs):
        cells = []
        for c, r in rep["configs"].items():
            x = r["rows"][i]
            cells.append("-" if x["psnr_db"] is None else f"{x['psnr_db']:.2f}" + (" (own)" if k == r["s_frac"] else ""))
        L.append(f"| {k} | " + " | ".join(cells) + " |")
    L += ["", f"Smallest s_frac at {db:g} dB (it and every larger s_frac at {db:g} dB or more): " + "; ".join(
        f"{c} {r['threshold_s_frac'] if r['threshold_s_frac'] is not None else 'not reached'}"
        for c, r in rep["configs"].items()) + f". Smallest s_frac within {PLATEAU_DB:g} dB of s_frac = {fracs[-1]}'s "
        "PSNR (where s_frac stops mattering beside the other formats): " + "; ".join(
        f"{c} {r['plateau_s_frac']}" for c, r in rep["configs"].items()) + ".", "",
        "## The configurations' s_frac", ""]
    for c, r in rep["configs"].items():
        t, own, p = r["threshold_s_frac"], r["s_frac"], r["psnr_at_own_s_frac_db"]
        best = max((x["psnr_db"] for x in r["rows"] if x["psnr_db"] is not None), default=None)
        if t is None:
            why = (f"no s_frac in {fracs[0]}..{fracs[-1]} reaches {db:g} dB on this scene (at most "
                   f"{best} dB: the configuration's other formats bound it), so s_frac is not what limits it")
        elif own >= t:
            why = (f"{own - t} bit(s) above the smallest s_frac that reaches {db:g} dB ({t}); "
                   + ("headroom for scenes that magnify more than this one" if own > t else
                      "no headroom for a scene that magnifies more"))
        else:
            why = f"{t - own} bit(s) below the {t} this scene needs for {db:g} dB: magnification shows its steps"
        L.append(f"- `{c}` (config/{c}.toml) has s_frac = {own} (s{r['s_w']}.{own}): {p} dB against its float "
                 f"reference here, {why}; within {PLATEAU_DB:g} dB of its best from s_frac = {r['plateau_s_frac']}.")
    errs = [(c, x) for c, r in rep["configs"].items() for x in r["rows"] if x.get("error")]
    if errs:
        L += ["", "Variants that are not valid or that the scene does not fit:", ""]
        L += [f"- {c} s_frac {x['s_frac']}: {x['error']}" for c, x in errs]
    qs = [(c, x) for c, r in rep["configs"].items() for x in r["rows"] if x.get("q")]
    if qs:
        L += ["", "Variants whose quadric words gave way (the golden model computes in int64, and the quadric's "
              "s x v product would need more than 62 bits: q_frac one bit narrower, its range kept):", ""]
        L += [f"- {c} s_frac {x['s_frac']}: q {x['q']}" for c, x in qs]
    L.append("")
    L.append(doc_stamp(list(rep["configs"])))
    (docs / "precision.md").write_text("\n".join(L) + "\n")


def main(argv=None) -> int:
    ap = Parser(prog="precision", description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=512, help="image width, 8..1024 (the paper: 512)")
    ap.add_argument("--configs", default=",".join(CONFIG_NAMES), help="comma-separated configurations")
    ap.add_argument("--fracs", default=f"{FRACS[0]}..{FRACS[-1]}", help="s_frac values: LO..HI or a comma list")
    ap.add_argument("--scene", default=str(SCENE), help="the scene (a .toml path or a scene name)")
    ap.add_argument("--db", type=float, default=DB, help="the PSNR threshold (dB)")
    ap.add_argument("--out", type=Path, help="output root (default out/; the docs then go to <out>/docs)")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)

    def go():
        text = a.fracs.strip()
        try:
            if ".." in text:
                lo, hi = (int(x) for x in text.split(".."))
                fracs = tuple(range(lo, hi + 1))
            else:
                fracs = tuple(int(x) for x in text.split(","))
        except ValueError:
            raise UserError(f"--fracs {a.fracs}: expected LO..HI or a comma-separated list of integers") from None
        if not fracs:
            raise UserError(f"--fracs {a.fracs}: no values")
        configs = tuple(x.strip() for x in a.configs.split(",") if x.strip())
        rep = run(a.size, configs, fracs, a.scene, a.db, a.out, progress=not a.quiet)
        print(json.dumps({c: {"threshold_s_frac": r["threshold_s_frac"], "plateau_s_frac": r["plateau_s_frac"],
                              "own_s_frac": r["s_frac"],
                              "psnr_at_own_db": r["psnr_at_own_s_frac_db"],
                              "psnr_db": {x["s_frac"]: x["psnr_db"] for x in r["rows"]}}
                          for c, r in rep["configs"].items()}))
        return 0

    return run_main("precision", go)


if __name__ == "__main__":
    sys.exit(main())
