"""Model backends behind the role registries: the registries and the CLI, the VLM hierarchy
against a chat-completions server on loopback and the co-refinement log's cases, and SAM3,
Qwen3-VL, Wan2.2 and a CoTracker3-contract tracker as tiny randomly initialised models built
here (nothing is downloaded)."""

from __future__ import annotations

import dataclasses
import importlib.util
import json
import subprocess
import sys
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import numpy as np
import pytest

from rest2art.backends import available, create, get
from rest2art.backends.check import backend_overrides, check_models
from rest2art.backends.vlm import TreeError, extract_json, parse_tree, tree_json
from rest2art.config import Config, ModelsConfig, OpenAIChatConfig, SegmentConfig, load_config
from rest2art.errors import ConfigError, ReconstructionError
from rest2art.generate import generate_object

HAS_TORCH = all(importlib.util.find_spec(p) for p in ("torch", "transformers"))
HAS_DIFFUSERS = HAS_TORCH and all(importlib.util.find_spec(p) for p in ("diffusers", "ftfy"))
HAS_OPENAI = importlib.util.find_spec("openai") is not None
needs_torch = pytest.mark.skipif(not HAS_TORCH, reason="needs the sam3 extra: pip install -e '.[sam3]'")
needs_diffusers = pytest.mark.skipif(not HAS_DIFFUSERS, reason="needs the video extra: pip install -e '.[video]'")
needs_openai = pytest.mark.skipif(not HAS_OPENAI, reason="needs the vlm extra: pip install -e '.[vlm]'")
needs_vlm = pytest.mark.skipif(not HAS_TORCH, reason="needs the vlm extra: pip install -e '.[vlm]'")


# -- registries and the command line ------------------------------------------------------------

def test_every_role_has_its_offline_default_and_its_model_backends():
    assert available("hierarchy") == ["geometric", "openai", "qwen3vl"]
    assert available("masks") == ["geometric", "sam3"]
    assert available("video") == ["none", "wan2.2"]
    assert available("tracks") == ["cotracker3", "lucas_kanade"]
    assert available("prompt") == ["openai", "qwen3vl", "template"]
    config = Config()
    assert (config.segment.hierarchy_backend, config.segment.masks_backend) == ("geometric", "geometric")
    assert (config.articulation.video_backend, config.articulation.tracks_backend) == ("none", "lucas_kanade")
    assert all(get(r, "geometric").packages == () for r in ("hierarchy", "masks"))


def test_a_wrong_backend_name_lists_the_valid_ones():
    with pytest.raises(ConfigError, match="segment.masks_backend: unknown backend 'sam4'. Valid: geometric, sam3"):
        get("masks", "sam4")
    with pytest.raises(ConfigError, match="ROLE one of hierarchy, masks, video, tracks, prompt"):
        backend_overrides(["segmenter=sam3"])
    assert backend_overrides(["masks=sam3", "tracks=cotracker3"]) == {
        "segment": {"masks_backend": "sam3"}, "articulation": {"tracks_backend": "cotracker3"}}


def test_a_model_backend_without_its_path_says_which_key_to_set():
    if not HAS_TORCH:
        pytest.skip("needs the sam3 extra: pip install -e '.[sam3]'")
    with pytest.raises(ConfigError, match="models.sam3.path is empty"):
        create("masks", "sam3", [], None, SegmentConfig(), ModelsConfig())


def test_models_check_reports_each_role_and_hints_for_what_is_missing(tmp_path):
    config = load_config(overrides={"segment": {"masks_backend": "sam3"},
                                    "models": {"sam3": {"path": str(tmp_path / "nowhere")}}})
    rows = {r.role: r for r in check_models(config)}
    assert rows["hierarchy"].ready and rows["tracks"].ready
    assert not rows["masks"].ready and any("nowhere not found" in m and "models.sam3.path" in m
                                           for m in rows["masks"].missing)
    cli = [sys.executable, "-m", "rest2art.cli", "models", "check"]
    ok = subprocess.run(cli, capture_output=True, text=True, timeout=120)
    assert ok.returncode == 0 and ok.stdout.strip().splitlines()[-1] == "all roles ready"
    bad = subprocess.run(cli + ["--backend", "video=wan2.2"], capture_output=True, text=True, timeout=120)
    assert bad.returncode == 3 and "models.wan.path" in bad.stdout and bad.stdout.strip().endswith("not ready: video")
    wrong = subprocess.run(cli + ["--backend", "video=sora"], capture_output=True, text=True, timeout=120)
    assert wrong.returncode == 2 and "Valid: none, wan2.2" in wrong.stderr and "Traceback" not in wrong.stderr


# -- the part tree as JSON ----------------------------------------------------------------------

def test_trees_are_read_from_fenced_json_and_checked():
    answer = 'Two doors, each with a handle.\n```json\n{"base": {"door_1": {"handle_1": {}}, "door_2": ["handle"]}}\n```'
    tree = parse_tree(extract_json(answer))
    assert tree.counts() == {"door": 2, "handle": 2}
    assert [n.parent for n in tree.nodes if n.category == "handle"] == ["door_0", "door_1"]
    assert parse_tree(json.loads(tree_json(tree))).counts() == tree.counts()
    with pytest.raises(TreeError, match="not valid JSON"):
        extract_json("```json\n{\"base\": {\"door_0\": }\n```")
    with pytest.raises(TreeError, match="exactly one root key 'base'"):
        parse_tree({"cabinet": {}})
    with pytest.raises(TreeError, match="a handle belongs to a door, drawer or lid"):
        parse_tree({"base": {"handle_0": {}}})
    with pytest.raises(TreeError, match="at most 2"):
        parse_tree({"base": {"door_0": ["handle", "handle", "handle"]}})
    with pytest.raises(TreeError, match="is not one of"):
        parse_tree({"base": {"shelf_0": {}}})


# -- a chat-completions peer on loopback --------------------------------------------------------

class ChatPeer:
    """A chat-completions server on 127.0.0.1 answering from a script: each entry is the reply
    text, or ("sleep", seconds); when the script runs out, ``default`` answers."""

    def __init__(self, default: str = ""):
        self.script: list = []
        self.default = default
        self.requests: list[dict] = []
        peer = self

        class Handler(BaseHTTPRequestHandler):
            def do_POST(self):
                body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
                peer.requests.append(body)
                reply = peer.script.pop(0) if peer.script else peer.default
                if isinstance(reply, tuple):
                    time.sleep(reply[1])
                    reply = peer.default
                data = json.dumps({"id": "chat-1", "object": "chat.completion", "created": 0, "model": body["model"],
                                   "choices": [{"index": 0, "finish_reason": "stop",
                                                "message": {"role": "assistant", "content": reply}}],
                                   "usage": {"prompt_tokens": 1, "completion_tokens": 1, "total_tokens": 2}}).encode()
                try:
                    self.send_response(200)
                    self.send_header("Content-Type", "application/json")
                    self.send_header("Content-Length", str(len(data)))
                    self.end_headers()
                    self.wfile.write(data)
                except (BrokenPipeError, ConnectionResetError):
                    pass  # the client gave up (timeout test)

            def log_message(self, *args):
                pass

        self.server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()
        self.url = f"http://127.0.0.1:{self.server.server_address[1]}/v1"

    def images(self, k: int) -> int:
        """Images sent in request ``k``."""
        return sum(1 for m in self.requests[k]["messages"] if isinstance(m["content"], list)
                   for c in m["content"] if c["type"] == "image_url")

    def close(self):
        self.server.shutdown()
        self.server.server_close()


def fenced(tree: dict) -> str:
    return f"The parts I see.\n```json\n{json.dumps(tree)}\n```"


@pytest.fixture
def peer():
    p = ChatPeer()
    yield p
    p.close()


@pytest.fixture(scope="module")
def drawers_scan():
    return generate_object("cabinet", 2, "scan")  # three drawers, one handle each


def true_tree(obj) -> dict:
    """The generated object's tree in the answer format: each movable part with one handle."""
    names = [p.semantic for p in obj.asset.parts if p.parent is not None]
    return {"base": {f"{s}_{k}": ({"handle_0": {}} if s in ("door", "drawer") else {}) for k, s in enumerate(names)}}


def vlm_config(peer, **changes) -> ModelsConfig:
    return ModelsConfig(openai=OpenAIChatConfig(base_url=peer.url, model="qwen3-vl", api_key_env="REST2ART_TEST_KEY",
                                                **{"views": 2, "image_size": 64, **changes}))


@needs_openai
def test_vlm_hierarchy_reasks_once_on_invalid_json_and_keeps_the_richest_tree(peer, drawers_scan):
    from rest2art.parts.segment.views import render_rig

    m = drawers_scan.mesh
    views = render_rig(m.vertices, m.faces, SegmentConfig(image_size=96))
    peer.script = ['```json\n{"base": {"drawer_0": }\n```',  # view 0: invalid ...
                   fenced({"base": {"drawer_0": {}}}),      # ... the re-ask answers
                   fenced(true_tree(drawers_scan))]          # view 11
    hierarchy = create("hierarchy", "openai", views, None, None, SegmentConfig(), vlm_config(peer))
    tree = hierarchy.propose(views)
    assert tree.counts() == {"drawer": 3, "handle": 3}
    assert len(peer.requests) == 3 and peer.images(0) == 1
    reask = peer.requests[1]["messages"]
    assert reask[-2]["role"] == "assistant" and "not valid JSON" in reask[-1]["content"]
    assert peer.requests[0]["temperature"] == 0.4 and peer.requests[0]["model"] == "qwen3-vl"
    assert "exactly one base" in peer.requests[0]["messages"][0]["content"]
    assert [e.get("invalid", "ok")[:14] for e in hierarchy.log] == ["not valid JSON", "ok", "ok"]


@needs_openai
def test_vlm_timeout_is_a_one_line_error_naming_the_endpoint(peer):
    from rest2art.backends.openai_chat import ChatClient
    from rest2art.backends.vlm import Message

    peer.script = [("sleep", 3.0)]
    client = ChatClient(OpenAIChatConfig(base_url=peer.url, model="gpt-test", timeout_s=0.5))
    start = time.perf_counter()
    with pytest.raises(ReconstructionError, match=r"gpt-test at http://127.0.0.1:\d+/v1: no answer within 0.5 s"):
        client.complete([Message("user", "hello")])
    assert time.perf_counter() - start < 2.5


def view_cases(log: list[dict], round_index: int) -> dict[int, str]:
    """{view: case} of the co-refinement log's entries in round ``round_index``."""
    return {e["view"]: e["case"] for e in log if "case" in e and e["round"] == round_index}


def test_a_views_case_is_excess_before_missing_and_excess_waits_in_the_last_round():
    from rest2art.parts.segment import corefine_action, corefine_case

    expected = {"door": 2, "handle": 2}
    assert corefine_case({"door": 2, "handle": 2}, expected) == "agree"
    assert corefine_case({"door": 2, "handle": 1}, expected) == "missing"
    assert corefine_case({"door": 3, "handle": 1}, expected) == "excess"  # the tree is incomplete first
    assert corefine_case({"knob": 1}, {}) == "excess"
    assert [corefine_action(c, last_round=False) for c in ("agree", "excess", "missing")] == [
        "cached", "revised", "deferred"]
    assert corefine_action("excess", last_round=True) == "deferred"


@needs_openai
def test_corefinement_with_the_vlm_revises_an_undercounted_tree_from_the_overlay(peer, drawers_scan):
    """The paper's loop: a tree with one drawer, views that show three (excess: the overlay goes
    back to the VLM, which answers the true tree), then views that agree."""
    from rest2art.parts.segment import COREFINE_CASES, PROPOSED, REVISED, segment_mesh
    from rest2art.parts.segment.roles import make_roles

    truth = true_tree(drawers_scan)
    peer.script = [fenced({"base": {"drawer_0": {"handle_0": {}}}})] * 2
    peer.default = fenced(truth)
    m = drawers_scan.mesh
    config = SegmentConfig(image_size=400, hierarchy_backend="openai")
    models = vlm_config(peer)
    seg = segment_mesh(m.vertices, m.faces, None, config, roles=lambda v, fp, c: make_roles(v, fp, c, models))
    log = seg.log["corefinement"]
    assert log[0]["event"] == PROPOSED and log[0]["counts"] == {"drawer": 1, "handle": 1}
    # round 0 stops at the first view with excess detections, whose overlay revises the tree
    first = [e for e in log if e["round"] == 0 and "case" in e]
    assert [e["case"] for e in first[:-1]] == ["agree"] * (len(first) - 1)
    assert first[-1]["case"] == "excess" and first[-1]["action"] == "revised"
    assert first[-1]["detected"]["drawer"] > first[-1]["expected"]["drawer"]
    revised = log[log.index(first[-1]) + 1]
    assert revised["event"] == REVISED and revised["counts"] == {"drawer": 3, "handle": 3}
    assert peer.images(2) == 1 and "segmentation model found" in peer.requests[2]["messages"][-1]["content"][-1]["text"]
    # round 1 checks every view again under the revised tree: no excess is left
    final = view_cases(log, 1)
    assert sorted(final) == list(range(len(seg.views))) and set(final.values()) <= set(COREFINE_CASES)
    assert "agree" in final.values() and "excess" not in final.values()
    assert seg.tree.counts() == {"drawer": 3, "handle": 3}
    assert sum(p.category == "drawer" for p in seg.parts) == 3


@needs_openai
def test_corefinement_with_the_true_tree_agrees_and_defers_views_with_missing_masks(peer, drawers_scan):
    """The VLM answers the true tree at once: views whose masks match it agree and are cached,
    views with fewer masks (one drawer dropped from view 0, as a segmenter may miss it, and
    views where drawers hide each other) are missing and deferred; the tree is never revised
    and the dropped drawer is still found from the other views."""
    from rest2art.parts.segment import REVISED, segment_mesh
    from rest2art.parts.segment.roles import GeometricBackend

    class MissOneDrawer(GeometricBackend):
        def segment(self, view, category):
            found = super().segment(view, category)
            return found[1:] if (view == 0 and category == "drawer") else found

    peer.default = fenced(true_tree(drawers_scan))
    m = drawers_scan.mesh
    config = SegmentConfig(image_size=400, hierarchy_backend="openai")
    models = vlm_config(peer)

    def roles(views, face_piece, config):
        masks = MissOneDrawer(views, face_piece, config)
        return create("hierarchy", "openai", views, face_piece, masks, config, models), masks

    seg = segment_mesh(m.vertices, m.faces, None, config, roles=roles)
    log = seg.log["corefinement"]
    assert not any(e.get("event") == REVISED for e in log) and max(e["round"] for e in log) == 0
    cases = view_cases(log, 0)
    assert sorted(cases) == list(range(len(seg.views))) and "excess" not in cases.values()
    assert cases[0] == "missing" and sum(c == "agree" for c in cases.values()) > len(cases) / 2
    for e in (e for e in log if "case" in e):
        below = any(n < e["expected"][s] for s, n in e["detected"].items())
        assert (e["case"], e["action"]) == (("missing", "deferred") if below else ("agree", "cached"))
    assert seg.tree.counts() == {"drawer": 3, "handle": 3}
    assert sum(p.category == "drawer" for p in seg.parts) == 3


# -- tiny models built from their library classes ----------------------------------------------

WORDS = ["<pad>", "<unk>", "<s>", "</s>", "door", "drawer", "lid", "knob", "handle", "tray", "the", "opens", "slides"]


def word_tokenizer():
    """A fast tokenizer over ``WORDS`` (what a checkpoint's tokenizer files hold, made here)."""
    from tokenizers import Tokenizer, models, pre_tokenizers
    from transformers import PreTrainedTokenizerFast

    tok = Tokenizer(models.WordLevel({w: i for i, w in enumerate(WORDS)}, unk_token="<unk>"))
    tok.pre_tokenizer = pre_tokenizers.Whitespace()
    return PreTrainedTokenizerFast(tokenizer_object=tok, pad_token="<pad>", unk_token="<unk>",
                                   bos_token="<s>", eos_token="</s>")


@pytest.fixture(scope="module")
def tiny_sam3(tmp_path_factory) -> Path:
    """A randomly initialised Sam3Model (2-layer ViT at 224 px) saved as a model folder."""
    import torch
    from transformers import Sam3Config, Sam3Model
    from transformers.models.sam3.configuration_sam3 import (
        Sam3DETRDecoderConfig,
        Sam3DETREncoderConfig,
        Sam3GeometryEncoderConfig,
        Sam3MaskDecoderConfig,
        Sam3VisionConfig,
        Sam3ViTConfig,
    )

    small = dict(num_attention_heads=4, intermediate_size=64)
    vit = Sam3ViTConfig(hidden_size=32, num_hidden_layers=2, image_size=224, patch_size=14, window_size=8,
                        global_attn_indexes=[0, 1], **small)
    config = Sam3Config(
        vision_config=Sam3VisionConfig(backbone_config=vit, fpn_hidden_size=32, scale_factors=[2.0, 1.0]),
        text_config=dict(vocab_size=len(WORDS), hidden_size=32, projection_dim=32, num_hidden_layers=2,
                         max_position_embeddings=32, hidden_act="gelu", bos_token_id=2, eos_token_id=3, **small),
        geometry_encoder_config=Sam3GeometryEncoderConfig(hidden_size=32, num_layers=1, mask_fuser_hidden_size=32,
                                                          mask_fuser_num_layers=1, **small),
        detr_encoder_config=Sam3DETREncoderConfig(hidden_size=32, num_layers=1, **small),
        detr_decoder_config=Sam3DETRDecoderConfig(hidden_size=32, num_layers=1, num_queries=5, **small),
        mask_decoder_config=Sam3MaskDecoderConfig(hidden_size=32, num_upsampling_stages=2))
    torch.manual_seed(0)
    folder = tmp_path_factory.mktemp("sam3")
    Sam3Model(config).save_pretrained(folder)
    word_tokenizer().save_pretrained(folder)
    (folder / "preprocessor_config.json").write_text(json.dumps(
        {"size": {"height": 224, "width": 224}, "image_mean": [0.5] * 3, "image_std": [0.5] * 3}))
    return folder


@needs_torch
def test_sam3_masks_come_back_per_view_and_prompt_at_the_view_size(tiny_sam3, drawers_scan):
    from rest2art.parts.segment.roles import InstanceMask
    from rest2art.parts.segment.views import render_rig

    m = drawers_scan.mesh
    views = render_rig(m.vertices, m.faces, SegmentConfig(image_size=120))[:2]
    models = ModelsConfig(sam3=dataclasses.replace(ModelsConfig().sam3, path=str(tiny_sam3), device="cpu",
                                                   score_threshold=0.0))
    masks = create("masks", "sam3", views, None, SegmentConfig(), models)
    found = masks.segment(1, "drawer")
    assert 1 <= len(found) <= 5 and all(isinstance(f, InstanceMask) for f in found)
    assert all(f.mask.shape == (120, 120) and f.mask.dtype == bool and 0.0 < f.score < 1.0 for f in found)
    assert masks.segment(1, "drawer") is found  # cached per view and prompt
    inside = np.argwhere(found[0].mask)[:10][:, ::-1]
    assert masks.segment_points(1, "drawer", inside) is not None
    strict = ModelsConfig(sam3=dataclasses.replace(models.sam3, score_threshold=1.0))
    assert create("masks", "sam3", views, None, SegmentConfig(), strict).segment(0, "door") == []


QWEN_TOKENS = ["<|im_start|>", "<|im_end|>", "<|vision_start|>", "<|vision_end|>", "<|image_pad|>", "<|video_pad|>"]

QWEN_TEMPLATE = ("{% for m in messages %}<|im_start|>{{ m['role'] }}\n{% if m['content'] is string %}{{ m['content'] }}"
                 "{% else %}{% for c in m['content'] %}{% if c['type'] == 'image' %}"
                 "<|vision_start|><|image_pad|><|vision_end|>{% else %}{{ c['text'] }}{% endif %}{% endfor %}{% endif %}"
                 "<|im_end|>\n{% endfor %}{% if add_generation_prompt %}<|im_start|>assistant\n{% endif %}")
"""A chat template in the form of Qwen3-VL's own: one vision block per image in a message."""


@pytest.fixture(scope="module")
def tiny_qwen3vl(tmp_path_factory) -> Path:
    """A randomly initialised Qwen3VLForConditionalGeneration (2 text and 2 vision layers, width
    32, 16 px patches) saved with its tokenizer, image processor and chat template, as a
    checkpoint folder holds them."""
    import torch
    from transformers import Qwen2VLImageProcessorPil, Qwen3VLConfig, Qwen3VLForConditionalGeneration

    tokenizer = word_tokenizer()
    tokenizer.add_special_tokens({"additional_special_tokens": QWEN_TOKENS})
    ids = {t: tokenizer.convert_tokens_to_ids(t) for t in QWEN_TOKENS}
    rope = {"rope_type": "default", "rope_theta": 10000.0, "mrope_section": [2, 1, 1], "mrope_interleaved": True}
    config = Qwen3VLConfig(
        text_config=dict(vocab_size=len(tokenizer), hidden_size=32, intermediate_size=64, num_hidden_layers=2,
                         num_attention_heads=4, num_key_value_heads=2, head_dim=8, max_position_embeddings=512,
                         rope_parameters=rope),
        vision_config=dict(depth=2, hidden_size=32, intermediate_size=64, num_heads=4, patch_size=16, out_hidden_size=32,
                           num_position_embeddings=64, deepstack_visual_indexes=[0]),
        image_token_id=ids["<|image_pad|>"], video_token_id=ids["<|video_pad|>"],
        vision_start_token_id=ids["<|vision_start|>"], vision_end_token_id=ids["<|vision_end|>"])
    torch.manual_seed(0)
    model = Qwen3VLForConditionalGeneration(config)
    model.generation_config.eos_token_id = ids["<|im_end|>"]
    model.generation_config.pad_token_id = tokenizer.pad_token_id
    folder = tmp_path_factory.mktemp("qwen3vl")
    model.save_pretrained(folder)
    tokenizer.save_pretrained(folder)
    Qwen2VLImageProcessorPil(patch_size=16, merge_size=2, temporal_patch_size=2, image_mean=[0.5] * 3,
                             image_std=[0.5] * 3, size={"shortest_edge": 32 * 32, "longest_edge": 64 * 64}
                             ).save_pretrained(folder)
    (folder / "chat_template.jinja").write_text(QWEN_TEMPLATE)
    return folder


@needs_vlm
def test_qwen3vl_loads_a_local_model_and_its_junk_ends_in_the_invalid_tree_error(tiny_qwen3vl, drawers_scan, tmp_path):
    """Qwen3-VL's loading and generation on a tiny random model: a rendered view becomes one
    image token per 2 x 2 patches, an answer stays within max_new_tokens, and the random words
    (this vocabulary has no braces) hold no tree, so each view is asked again once and the
    hierarchy fails with the same one-line error as over the chat API."""
    import shutil

    import torch

    from rest2art.backends.vlm import ASK_PROMPT, Message, resize_square
    from rest2art.joints.video.source import PROMPT_SUFFIX
    from rest2art.parts.segment.views import render_rig

    m = drawers_scan.mesh
    views = render_rig(m.vertices, m.faces, SegmentConfig(image_size=96))
    budget = 6
    models = ModelsConfig(qwen3vl=dataclasses.replace(ModelsConfig().qwen3vl, path=str(tiny_qwen3vl), device="cpu",
                                                      max_new_tokens=budget, views=2, image_size=64))
    hierarchy = create("hierarchy", "qwen3vl", views, None, None, SegmentConfig(), models)
    client = hierarchy.client
    messages = [Message("user", ASK_PROMPT, [resize_square(views[0].shaded(), 64)])]
    inputs = client.encode(messages)
    assert inputs["image_grid_thw"].tolist() == [[1, 4, 4]]  # 64 px in 16 px patches
    image_tokens = inputs["input_ids"] == client.tokenizer.convert_tokens_to_ids("<|image_pad|>")
    assert image_tokens.sum() == 4 and torch.equal(inputs["mm_token_type_ids"].bool(), image_tokens)
    torch.manual_seed(0)
    answer = client.complete(messages)
    assert 0 < len(client.tokenizer(answer, add_special_tokens=False)["input_ids"]) <= budget

    with pytest.raises(ReconstructionError) as error:
        hierarchy.propose(views)
    assert str(error.value).startswith("hierarchy backend 'qwen3vl': no valid part tree in any answer (not valid JSON")
    assert "\n" not in str(error.value)
    assert [(e["view"], e["attempt"]) for e in hierarchy.log] == [(0, 0), (0, 1), (11, 0), (11, 1)]
    assert all(e["invalid"].startswith("not valid JSON") for e in hierarchy.log)
    assert create("prompt", "qwen3vl", models)(views[0].shaded(), ["drawer"]).endswith(PROMPT_SUFFIX)

    bare = tmp_path / "bare"
    shutil.copytree(tiny_qwen3vl, bare, ignore=shutil.ignore_patterns("chat_template.jinja"))
    with pytest.raises(ConfigError, match="models.qwen3vl.path: .* holds no chat template"):
        create("hierarchy", "qwen3vl", views, None, None, SegmentConfig(),
               ModelsConfig(qwen3vl=dataclasses.replace(models.qwen3vl, path=str(bare))))


TRACKER_SOURCE = '''
import torch

class Drift(torch.nn.Module):
    """CoTracker3's contract: (1, T, 3, H, W) video, (1, N, 3) (t, x, y) queries ->
    (1, T, N, 2) tracks and (1, T, N) visibility; here every point drifts 1 px right per frame
    and is lost from frame 3 on where x > 60."""

    def forward(self, video: torch.Tensor, queries: torch.Tensor):
        T = video.shape[1]
        t = torch.arange(T, dtype=torch.float32).view(1, T, 1)
        xy = queries[:, None, :, 1:].repeat(1, T, 1, 1)
        xy[..., 0] = xy[..., 0] + t
        visible = ~((t >= 3) & (xy[..., 0] > 60))
        return xy, visible
'''


@pytest.fixture(scope="module")
def tiny_tracker(tmp_path_factory) -> Path:
    """A TorchScript tracker with CoTracker3's input/output contract."""
    import importlib

    import torch

    folder = tmp_path_factory.mktemp("cotracker")
    (folder / "drift_tracker.py").write_text(TRACKER_SOURCE)
    sys.path.insert(0, str(folder))
    try:
        module = importlib.import_module("drift_tracker")
    finally:
        sys.path.remove(str(folder))
    path = folder / "drift.pt"
    torch.jit.script(module.Drift()).save(str(path))
    return path


@needs_torch
def test_cotracker3_tracks_follow_the_tracks_contract(tiny_tracker):
    models = ModelsConfig(cotracker=dataclasses.replace(ModelsConfig().cotracker, path=str(tiny_tracker), device="cpu"))
    tracker = create("tracks", "cotracker3", models)
    frames = np.zeros((6, 40, 80, 3), np.uint8)
    queries = np.array([[10.5, 5.5], [59.5, 20.5]])
    tracks = tracker.track(frames, queries)
    assert tracks.xy.shape == (6, 2, 2) and tracks.visible.shape == (6, 2)
    assert np.allclose(tracks.xy[:, 0, 0], 10.5 + np.arange(6)) and np.allclose(tracks.xy[:, :, 1], [5.5, 20.5])
    assert tracks.visible[:, 0].all() and tracks.visible[:3, 1].all() and not tracks.visible[3:, 1].any()


def tiny_wan_pipeline():
    """A randomly initialised Wan2.2 A14B-style image-to-video pipeline (two transformers)."""
    import torch
    from diffusers import AutoencoderKLWan, UniPCMultistepScheduler, WanImageToVideoPipeline, WanTransformer3DModel
    from transformers import T5Config, T5EncoderModel

    torch.manual_seed(0)
    vae = AutoencoderKLWan(base_dim=3, z_dim=16, dim_mult=[1, 1, 1, 1], num_res_blocks=1,
                           temperal_downsample=[False, True, True])
    text = T5EncoderModel(T5Config(vocab_size=len(WORDS), d_model=32, d_ff=37, d_kv=8, num_layers=2, num_heads=4,
                                   relative_attention_num_buckets=8))
    shape = dict(patch_size=(1, 2, 2), num_attention_heads=2, attention_head_dim=12, in_channels=36, out_channels=16,
                 text_dim=32, freq_dim=256, ffn_dim=32, num_layers=2, cross_attn_norm=True,
                 qk_norm="rms_norm_across_heads", rope_max_seq_len=32)
    return WanImageToVideoPipeline(
        transformer=WanTransformer3DModel(**shape), transformer_2=WanTransformer3DModel(**shape), vae=vae,
        scheduler=UniPCMultistepScheduler(prediction_type="flow_prediction", use_flow_sigmas=True, flow_shift=3.0),
        text_encoder=text, tokenizer=word_tokenizer(), image_encoder=None, image_processor=None, boundary_ratio=0.875)


@pytest.fixture(scope="module")
def tiny_wan(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("wan")
    tiny_wan_pipeline().save_pretrained(folder)
    return folder


def wan_models(folder: Path) -> ModelsConfig:
    return ModelsConfig(wan=dataclasses.replace(ModelsConfig().wan, path=str(folder), device="cpu", size=32, steps=2))


@needs_diffusers
def test_wan_video_animates_the_conditioning_image_at_its_size(tiny_wan):
    video = create("video", "wan2.2", wan_models(tiny_wan))
    image = np.full((48, 40, 3), 128, np.uint8)
    frames = video.generate(image, "the drawer slides", seed=0, n_frames=7)
    assert frames.shape == (9, 48, 40, 3) and frames.dtype == np.uint8  # 4k + 1 frames
    again = video.generate(image, "the drawer slides", seed=0, n_frames=7)
    other = video.generate(image, "the drawer slides", seed=1, n_frames=7)
    assert np.array_equal(frames, again) and not np.array_equal(frames, other)


@pytest.mark.slow
@needs_diffusers
@needs_openai
def test_the_pipeline_runs_with_every_role_on_its_model_backend(peer, tiny_sam3, tiny_tracker, tiny_wan, tmp_path):
    """Generated drawer unit (asset variant); hierarchy and video prompt from the chat peer,
    SAM3, Wan2.2 and the tracker tiny and random: the asset is whole and valid, the tracks
    (a drift to the right) reach the joint evidence, the debug folder holds the videos."""
    from rest2art.export.writers import write_asset
    from rest2art.generate import write_object
    from rest2art.pipeline import complete_asset, reconstruct_file

    obj = generate_object("cabinet", 2, "asset")
    path = write_object(obj, tmp_path / "in")
    peer.default = fenced(true_tree(obj))
    models = dataclasses.replace(vlm_config(peer), sam3=dataclasses.replace(
        ModelsConfig().sam3, path=str(tiny_sam3), device="cpu"), cotracker=dataclasses.replace(
        ModelsConfig().cotracker, path=str(tiny_tracker), device="cpu"), wan=wan_models(tiny_wan).wan)
    config = dataclasses.replace(
        Config(), models=models,
        segment=dataclasses.replace(Config().segment, hierarchy_backend="openai", masks_backend="sam3", image_size=200),
        articulation=dataclasses.replace(Config().articulation, video_backend="wan2.2", tracks_backend="cotracker3",
                                         prompt_backend="openai", video_frames=9))
    debug: dict = {}
    asset, mesh = reconstruct_file(path, config, debug=debug)
    complete_asset(asset, config)
    asset.validate()
    (tmp_path / "out").mkdir()
    write_asset(asset, tmp_path / "out", "cabinet", config.export)
    assert (tmp_path / "out" / "articulation.json").is_file()
    assert len(asset.face_part) == len(mesh.faces)
    assert debug["video_prompt"].endswith("No camera movement. Camera locked.")
    assert sorted(debug["motion_videos"]) == [0, 1] or len(debug["motion_videos"]) == 4
    assert all(v.shape[0] == 9 for v in debug["motion_videos"].values())
    videos = [e for e in asset.metadata["joints"].values() if "video" in e or "motion video" in str(e.get("rule"))]
    assert videos, "the tracked motion reached no joint"
