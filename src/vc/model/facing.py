"""The facing model: two small networks per compile, trained on the compile's renders, that read from a person's
crop whether they are seen from the front or from behind, and where their face points across the image
(:mod:`vc.deploy.facing` runs them).

Why a model of its own: which way a person faces decides all eight left/right pairs at once, and the region networks'
handedness maps, one output among 27 of a network sized for finding people, stay near chance on PETS09's 48 px
people even on their own renders. A classifier that sees only the person and answers only that learns it on the
same renders (held-out accuracy 0.94-0.96 on PETS09's and TUD-Stadtmitte's), and on real frames it is right for
about two people in three (PETS09) to four in five (TUD-Stadtmitte) where the networks' reading is at chance
(docs/decisions/0027-facing-from-the-crop.md). Where the face points is read the same way: the networks put the
nose between the ears, and a person crossing the view shows it ahead of them; the same network, trained for that,
reads it on real people as it does on renders (docs/decisions/0038-the-face-turned-from-the-crop.md).

1. **Crops**: every rendered person seen whole (visible box at least :data:`MIN_VISIBLE_SHARE` of the amodal box's
   height, amodal height at least :data:`MIN_HEIGHT_PX`), cut from the region's render by the graph the bundle's
   model cuts frames with (:func:`crop_graph`). Each is labelled front or behind by the 3-D keypoints' image order
   (the dataset's ``left_is_image_left``) on shoulders and hips together; people in profile, whose pairs disagree or
   lie within :data:`PROFILE_SHARE` of their height, have no front to learn and no such label. Each is also labelled
   with where the face points (:func:`face_across`): the nose's offset from the ears' midpoint over the distance
   the body model puts it ahead of them in profile.
2. **Camera look**: each crop drawn for training is blurred, cast, dimmed or brightened, given gain noise, compressed
   or made monochrome (:func:`camera_look`), and mirrored half the time (a mirror keeps the front a front and turns
   the face the other way).
3. **Training**: :class:`FacingNet` with binary cross-entropy, and :class:`FaceTurnNet` with the squared error of
   where the face points, each with AdamW and a one-cycle schedule, seeded; the dataset's held-out shards (the
   region networks' own) measure them. The classifier a compile ships is distilled
   (:func:`train_distilled_facing`): :data:`MEMBERS` classifiers trained from their own seeds, then one trained the
   same way to each crop's mean probability of a front over them. Which real people one classifier reads the wrong
   way round depends much on its seed; the members' mean depends less on it, and one network that learnt it costs
   one network's time (docs/decisions/0063-the-facing-classifier-distilled-from-three.md).
4. **The head's colours** (:class:`HeadColours`): front from behind read a second way, by a linear model that sees
   only where the head's window of the crop is lighter or darker, trained on the same crops
   (:func:`train_head_colours`).
   The classifier learns the renders' people exactly (0.99 AUC on held-out renders) and carries little of it to
   PETS09's small people seen from above (AUC 0.55-0.82 on real people); a model that can weigh nothing but the
   head's light and dark learns what real faces share with rendered ones, a light face under darker hair, and reads
   them better (AUC 0.73-0.86). The runtime reads it for people too small for the classifier
   (docs/decisions/0041-the-heads-colours-for-small-people.md).
5. **Export** (:func:`vc.model.export.export_facing`): the crop graph and the networks as one ONNX graph, a frame
   and the crops' rectangles in, per person a logit, where the face points and the head's logit out.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
import onnx
import onnxruntime as ort
import torch
from onnx import TensorProto, helper
from scipy.stats import rankdata
from torch import Tensor, nn
from tqdm import tqdm

from vc.deploy.facing import CROP_SIZE, FACE_AHEAD_OF_EARS, FRAME_INPUT, ROIS_INPUT, crop_rois
from vc.deploy.heatmaps import PAIRS
from vc.io import read_image
from vc.keypoints import COCO_KEYPOINTS
from vc.render.dataset import Sample, open_region, read_manifest

#: A person is cropped when their visible box is at least this share of their whole body's height ...
MIN_VISIBLE_SHARE = 0.8
#: ... and the body at least this tall in the region's render (pixels).
MIN_HEIGHT_PX = 20.0
#: Shoulders' and hips' left-minus-right offsets summed under this share of the person's height: in profile.
PROFILE_SHARE = 0.06
#: The pairs that say which way the body faces (their index in :data:`vc.deploy.heatmaps.PAIRS`).
TORSO_PAIRS = tuple(index for index, (left, _) in enumerate(PAIRS)
                    if COCO_KEYPOINTS[left] in ("left_shoulder", "left_hip"))
#: Where a run keeps the facing model and what it measured (``vc-train`` writes them, ``vc-export`` ships the model).
FACING_MODEL, FACING_REPORT = "facing.onnx", "facing.json"
#: Fewer people facing the camera or away from it than this leave the model unlearnt: a run trains none.
MIN_FACING_CROPS = 1000
#: Bilinear samples per crop pixel and axis, averaged (RoiAlign's ``sampling_ratio``). As many as the frame has pixels
#: there cost 3.3 ms a TUD-Stadtmitte frame of seven near people; two cost 1.2 ms.
CROP_SAMPLES = 2
#: The crop graph's ONNX opset (RoiAlign's half-pixel coordinates came with 16).
FACING_OPSET = 17
#: Training schedule.
EPOCHS = 8
#: The shipped classifier learns the mean of this many, trained from seeds this far apart (step 3).
MEMBERS, MEMBER_SEED_STRIDE = 3, 1000
BATCH = 128
LEARNING_RATE = 3e-3
#: The head's window in the crop (rows, then columns, of the 64 x 32 crop): the head of a person framed by their box,
#: whatever their size, with room for a box drawn a little higher or lower (step 4).
HEAD_ROWS, HEAD_COLUMNS = (2, 18), (10, 22)
#: The window is read in cells of this many crop pixels a side: 8 x 6 cells of three colours.
HEAD_CELL = 2
#: Each crop's cells are taken less their mean, over their spread plus this (crop values run 0-1): where the head is
#: lighter or darker counts, not how bright the frame is; the floor keeps a flat window's noise from being inflated.
HEAD_SPREAD_FLOOR = 4.0 / 255.0
#: Training draws this many crops, each in :data:`HEAD_LOOKS` camera looks, moved up or down by up to
#: :data:`HEAD_SHIFT_ROWS` rows and sideways by a column (a box drawn higher, lower or off centre), mirrored half
#: the time; the fit is full-batch L-BFGS with this L2 weight on the weights (docs/decisions/0041).
HEAD_CROPS, HEAD_LOOKS, HEAD_SHIFT_ROWS = 6000, 3, 3
HEAD_L2 = 1e-3
HEAD_ITERATIONS = 200


class FacingNet(nn.Module):
    """Conv-BN-ReLU stages over the 64x32 crop, halving it three times, then a global average and one logit."""

    def __init__(self, widths: tuple[int, ...] = (8, 16, 32)) -> None:
        super().__init__()
        layers: list[nn.Module] = []
        channels = 3
        for index, width in enumerate(widths):
            layers += [_stage(channels, width), _stage(width, width)]
            if index < len(widths) - 1:
                layers.append(nn.MaxPool2d(2))
            channels = width
        self.features = nn.Sequential(*layers, nn.MaxPool2d(2), _stage(channels, channels))
        self.logit = nn.Linear(channels, 1)

    def forward(self, crops: Tensor) -> Tensor:
        return self.logit(self.features(crops).mean(dim=(2, 3))).squeeze(1)


class FaceTurnNet(FacingNet):
    """:class:`FacingNet` with its output through tanh: where the face points across the image, -1 to 1."""

    def forward(self, crops: Tensor) -> Tensor:
        return torch.tanh(super().forward(crops))


class HeadColours(nn.Module):
    """The head reader (step 4): the crop's head window in cells of :data:`HEAD_CELL` pixels, each crop's cells
    standardised, and one linear logit, > 0 seen from the front."""

    def __init__(self) -> None:
        super().__init__()
        cells = ((HEAD_ROWS[1] - HEAD_ROWS[0]) // HEAD_CELL) * ((HEAD_COLUMNS[1] - HEAD_COLUMNS[0]) // HEAD_CELL)
        self.logit = nn.Linear(3 * cells, 1)

    @staticmethod
    def cells(crops: Tensor) -> Tensor:
        """The head's window of ``crops`` (N, 3, 64, 32) as (N, 144) cells, each crop's standardised."""
        window = crops[:, :, HEAD_ROWS[0]:HEAD_ROWS[1], HEAD_COLUMNS[0]:HEAD_COLUMNS[1]]
        cells = nn.functional.avg_pool2d(window, HEAD_CELL).flatten(1)
        centred = cells - cells.mean(dim=1, keepdim=True)
        spread = centred.square().mean(dim=1, keepdim=True).sqrt()
        return centred / (spread + HEAD_SPREAD_FLOOR)

    def forward(self, crops: Tensor) -> Tensor:
        return self.logit(self.cells(crops)).squeeze(1)


def _stage(inputs: int, outputs: int) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(inputs, outputs, 3, padding=1, bias=False), nn.BatchNorm2d(outputs),
                         nn.ReLU(inplace=True))


@dataclass(frozen=True)
class FacingCrops:
    """Crops (N, 64, 32, 3) uint8 and whether each person is seen from the front (N,) bool."""

    crops: np.ndarray
    front: np.ndarray

    def __len__(self) -> int:
        return len(self.front)


@dataclass(frozen=True)
class TurnCrops:
    """Crops (N, 64, 32, 3) uint8 and where each person's face points across the image (N,) float, -1 to 1."""

    crops: np.ndarray
    across: np.ndarray

    def __len__(self) -> int:
        return len(self.across)


@dataclass(frozen=True)
class PersonCrops:
    """The crops of a set of renders, for each model its own: whole people facing the camera or away from it, and
    whole people whose nose and ears are labelled."""

    facing: FacingCrops
    turn: TurnCrops


def seen_from_front(annotation: dict) -> bool | None:
    """Whether a rendered person is seen from the front (their left shoulder and hip on the image's right), behind,
    or None in profile (step 1)."""
    order = [annotation["left_is_image_left"][index] for index in TORSO_PAIRS]
    if len(set(order)) > 1:
        return None
    labels = np.reshape(annotation["keypoints"], (-1, 3))
    offset = sum(labels[PAIRS[index][0], 0] - labels[PAIRS[index][1], 0] for index in TORSO_PAIRS)
    height = annotation["amodal_bbox"][3]
    if abs(offset) < PROFILE_SHARE * height:
        return None
    return not order[0]


def face_across(annotation: dict) -> float | None:
    """Where a rendered person's face points across the image (step 1): the nose's horizontal offset from the ears'
    midpoint over :data:`~vc.deploy.facing.FACE_AHEAD_OF_EARS`'s nose distance, clipped to -1 (in profile facing the
    image's left) .. 1 (facing its right); None when the nose or an ear is not labelled."""
    labels = np.reshape(annotation["keypoints"], (-1, 3))
    nose, ears = COCO_KEYPOINTS.index("nose"), [COCO_KEYPOINTS.index(name) for name in ("left_ear", "right_ear")]
    if labels[nose, 2] <= 0 or (labels[ears, 2] <= 0).any():
        return None
    offset = (labels[nose, 0] - labels[ears, 0].mean()) / annotation["amodal_bbox"][3]
    return float(np.clip(offset / FACE_AHEAD_OF_EARS["nose"], -1.0, 1.0))


#: The crop graph's output, the classifier's input.
CROPS = "crops"


def crop_graph(size: tuple[int, int] = CROP_SIZE) -> onnx.ModelProto:
    """The ONNX graph that cuts people's crops out of a frame (step 1 of :mod:`vc.deploy.facing`): the frame (1, H,
    W, 3) uint8 and the rectangles (N, 4) in, the crops (N, 3, height, width) float in [0, 1] out at ``size``
    (width, height; the facing model's by default), each bin the average of :data:`CROP_SAMPLES` x
    :data:`CROP_SAMPLES` bilinear samples."""
    nodes = [
        helper.make_node("Cast", [FRAME_INPUT], ["frame_float"], to=TensorProto.FLOAT),
        helper.make_node("Transpose", ["frame_float"], ["frame_nchw"], perm=[0, 3, 1, 2]),
        helper.make_node("Shape", [ROIS_INPUT], ["rois_shape"]),
        helper.make_node("Gather", ["rois_shape", "zero"], ["count"], axis=0),
        helper.make_node("Unsqueeze", ["count", "first_axis"], ["count_1d"]),
        helper.make_node("ConstantOfShape", ["count_1d"], ["frame_index"],
                         value=helper.make_tensor("frame_0", TensorProto.INT64, [1], [0])),
        helper.make_node("RoiAlign", ["frame_nchw", ROIS_INPUT, "frame_index"], ["crops_255"], mode="avg",
                         output_height=size[1], output_width=size[0], sampling_ratio=CROP_SAMPLES,
                         spatial_scale=1.0,
                         coordinate_transformation_mode="half_pixel"),
        helper.make_node("Mul", ["crops_255", "one_over_255"], [CROPS]),
    ]
    graph = helper.make_graph(
        nodes, "facing_crops",
        [helper.make_tensor_value_info(FRAME_INPUT, TensorProto.UINT8, [1, "height", "width", 3]),
         helper.make_tensor_value_info(ROIS_INPUT, TensorProto.FLOAT, ["people", 4])],
        [helper.make_tensor_value_info(CROPS, TensorProto.FLOAT, ["people", 3, size[1], size[0]])],
        initializer=[helper.make_tensor("zero", TensorProto.INT64, [], [0]),
                     helper.make_tensor("first_axis", TensorProto.INT64, [1], [0]),
                     helper.make_tensor("one_over_255", TensorProto.FLOAT, [], [1.0 / 255.0])])
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", FACING_OPSET)])
    onnx.checker.check_model(model)
    return model


def crops_of(samples: list[Sample]) -> PersonCrops:
    """Every whole person of ``samples``, cropped by :func:`crop_graph` (step 1): those facing the camera or away
    from it for the facing classifier, those whose nose and ears are labelled for the face turn."""
    session = ort.InferenceSession(crop_graph().SerializeToString(), providers=["CPUExecutionProvider"])
    crops, front, across = [], [], []
    for sample in samples:
        boxes = []
        for annotation in sample.annotations:
            x, y, width, height = annotation["amodal_bbox"]
            if height < MIN_HEIGHT_PX or annotation["bbox"][3] < MIN_VISIBLE_SHARE * height:
                continue
            seen, turned = seen_from_front(annotation), face_across(annotation)
            if seen is not None or turned is not None:
                boxes.append([x, y, x + width, y + height])
                front.append(seen)
                across.append(turned)
        if not boxes:
            continue
        image = read_image(sample.image_path)  # the render alone: its instance map is not needed
        cut = session.run(None, {FRAME_INPUT: image[None], ROIS_INPUT: crop_rois(np.array(boxes))})[0]
        crops.append(np.clip(np.rint(cut.transpose(0, 2, 3, 1) * 255.0), 0, 255).astype(np.uint8))
    every = np.concatenate(crops) if crops else np.zeros((0, CROP_SIZE[1], CROP_SIZE[0], 3), np.uint8)
    facing = np.array([seen is not None for seen in front], bool)
    turning = np.array([turned is not None for turned in across], bool)
    return PersonCrops(FacingCrops(every[facing], np.array([seen for seen in front if seen is not None], bool)),
                       TurnCrops(every[turning], np.array([turned for turned in across if turned is not None],
                                                          np.float32)))


def dataset_crops(dataset: Path) -> tuple[PersonCrops, PersonCrops]:
    """The training and held-out crops of every region of a rendered ``dataset``."""
    train, held_out = [], []
    for region in read_manifest(dataset).get("regions", {}):
        data = open_region(dataset, region)
        train.append(crops_of(data.train))
        held_out.append(crops_of(data.held_out))
    return _joined(train), _joined(held_out)


def _joined(parts: list[PersonCrops]) -> PersonCrops:
    return PersonCrops(
        FacingCrops(np.concatenate([part.facing.crops for part in parts]),
                    np.concatenate([part.facing.front for part in parts])),
        TurnCrops(np.concatenate([part.turn.crops for part in parts]),
                  np.concatenate([part.turn.across for part in parts])))


def camera_look(crop: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """One draw of the camera's look on a uint8 crop (step 2): the range a surveillance camera's people show."""
    out = crop.astype(np.float32)
    if rng.random() < 0.7:
        out = cv2.GaussianBlur(out, (0, 0), rng.uniform(0.3, 1.3))
    out = out * rng.uniform(0.75, 1.25, 3).astype(np.float32) * np.float32(rng.uniform(0.5, 1.4))
    if rng.random() < 0.5:
        out = out + rng.normal(0.0, rng.uniform(1.0, 8.0), out.shape).astype(np.float32)
    out = np.clip(out, 0, 255).astype(np.uint8)
    if rng.random() < 0.5:
        _, encoded = cv2.imencode(".jpg", out, [cv2.IMWRITE_JPEG_QUALITY, int(rng.integers(30, 90))])
        out = cv2.imdecode(encoded, cv2.IMREAD_UNCHANGED)
    if rng.random() < 0.3:
        out = np.repeat(out.mean(axis=2, keepdims=True), 3, axis=2).astype(np.uint8)
    return out


def _batch(crops: np.ndarray) -> Tensor:
    return torch.from_numpy(np.ascontiguousarray(crops)).permute(0, 3, 1, 2).float() / 255.0


def _rounded(share: float | None) -> float | None:
    return None if share is None else round(share, 4)


@dataclass(frozen=True)
class FacingResult:
    net: FacingNet
    held_out_accuracy: float | None  # share of held-out people read the right way; None without any
    train_crops: int
    held_out_crops: int
    seconds: float
    members_held_out_accuracy: tuple[float | None, ...] = ()  # the members' it learnt from, where distilled

    def to_dict(self) -> dict:
        measured = {"held_out_accuracy": _rounded(self.held_out_accuracy), "train_crops": self.train_crops,
                    "held_out_crops": self.held_out_crops, "seconds": round(self.seconds, 1)}
        if self.members_held_out_accuracy:
            measured["members_held_out_accuracy"] = [_rounded(share) for share in self.members_held_out_accuracy]
        return measured


@dataclass(frozen=True)
class FaceTurnResult:
    net: FaceTurnNet
    held_out_error: float | None  # mean absolute error of where the held-out faces point; None without any
    held_out_profile_sign: float | None  # share of held-out people in profile (|across| >= 0.5) read the right way
    train_crops: int
    held_out_crops: int
    seconds: float

    def to_dict(self) -> dict:
        return {"held_out_error": None if self.held_out_error is None else round(self.held_out_error, 4),
                "held_out_profile_sign": (None if self.held_out_profile_sign is None
                                          else round(self.held_out_profile_sign, 4)),
                "train_crops": self.train_crops, "held_out_crops": self.held_out_crops,
                "seconds": round(self.seconds, 1)}


@dataclass(frozen=True)
class HeadResult:
    net: HeadColours
    held_out_accuracy: float | None  # share of held-out people read the right way; None without any
    held_out_auc: float | None  # how well its logit ranks them, front above behind
    train_crops: int
    seconds: float

    def to_dict(self) -> dict:
        return {"held_out_accuracy": None if self.held_out_accuracy is None else round(self.held_out_accuracy, 4),
                "held_out_auc": None if self.held_out_auc is None else round(self.held_out_auc, 4),
                "train_crops": self.train_crops, "seconds": round(self.seconds, 1)}


def _outputs(net: nn.Module, crops: np.ndarray) -> np.ndarray:
    net.eval()
    with torch.no_grad():
        return torch.cat([net(_batch(crops[start:start + 512])) for start in range(0, len(crops), 512)]).numpy()


def ranking(logits: np.ndarray, front: np.ndarray) -> float | None:
    """The area under the ROC curve of ``logits`` for ``front``: the chance that a person seen from the front scores
    above one seen from behind (ties count half); None without both."""
    front = np.asarray(front, bool)
    fronts = int(front.sum())
    if fronts in (0, len(front)):
        return None
    ranks = rankdata(logits)
    return float((ranks[front].sum() - fronts * (fronts + 1) / 2) / (fronts * (len(front) - fronts)))


def accuracy(net: nn.Module, crops: FacingCrops) -> float | None:
    """The share of ``crops`` whose facing ``net`` reads right."""
    if not len(crops):
        return None
    return float(((_outputs(net, crops.crops) > 0) == crops.front).mean())


def _fit(net: FacingNet, crops: np.ndarray, targets: np.ndarray, loss_of: nn.Module, mirror_sign: float,
         seed: int, epochs: int, show_progress: bool, description: str) -> None:
    """Step 3 for either network: ``epochs`` over ``crops`` in the camera's look, each mirrored half the time, its
    target then times ``mirror_sign`` (1: a mirror keeps it, -1: a mirror turns it round)."""
    rng = np.random.default_rng(seed)
    steps_per_epoch = len(crops) // BATCH
    optimiser = torch.optim.AdamW(net.parameters(), LEARNING_RATE / 1.5, weight_decay=1e-4)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimiser, LEARNING_RATE, total_steps=epochs * steps_per_epoch)
    labels = torch.from_numpy(targets.astype(np.float32))
    with tqdm(total=epochs * steps_per_epoch, desc=description, unit="step", disable=not show_progress,
              leave=False) as bar:
        for _ in range(epochs):
            net.train()
            order = rng.permutation(len(crops))
            for step in range(steps_per_epoch):
                chosen = order[step * BATCH:(step + 1) * BATCH]
                looks = np.stack([camera_look(crop, rng) for crop in crops[chosen]])
                mirrored = rng.random(len(chosen)) < 0.5
                looks[mirrored] = looks[mirrored, :, ::-1]
                target = labels[chosen] * torch.from_numpy(np.where(mirrored, mirror_sign, 1.0).astype(np.float32))
                loss = loss_of(net(_batch(looks)), target)
                optimiser.zero_grad()
                loss.backward()
                optimiser.step()
                schedule.step()
                bar.update()


def train_facing(train: FacingCrops, held_out: FacingCrops, seed: int, epochs: int = EPOCHS,
                 show_progress: bool = True) -> FacingResult:
    """Train a :class:`FacingNet` on ``train`` and measure it on ``held_out`` (step 3); the same ``seed`` gives the
    same weights on one kind of CPU."""
    if len(train) < BATCH:
        raise ValueError(f"{len(train)} rendered people face the camera or away from it; the facing model needs "
                         f"{BATCH} or more")
    start = time.perf_counter()
    torch.manual_seed(seed)
    net = FacingNet()
    _fit(net, train.crops, train.front, nn.BCEWithLogitsLoss(), 1.0, seed, epochs, show_progress, "facing")
    return FacingResult(net, accuracy(net, held_out), len(train), len(held_out), time.perf_counter() - start)


def train_distilled_facing(train: FacingCrops, held_out: FacingCrops, seed: int, members: int = MEMBERS,
                           epochs: int = EPOCHS, show_progress: bool = True) -> FacingResult:
    """Train ``members`` classifiers as :func:`train_facing` does, from seeds ``seed``, ``seed`` +
    :data:`MEMBER_SEED_STRIDE`, ..., then one :class:`FacingNet` from ``seed`` on each training crop's mean
    probability of a front over them instead of its label, and measure it on ``held_out`` (step 3). The same
    ``seed`` gives the same weights on one kind of CPU."""
    start = time.perf_counter()
    trained = [train_facing(train, held_out, seed + index * MEMBER_SEED_STRIDE, epochs, show_progress)
               for index in range(members)]
    fronts = np.mean([1.0 / (1.0 + np.exp(-_outputs(member.net, train.crops))) for member in trained], axis=0)
    torch.manual_seed(seed)
    net = FacingNet()
    _fit(net, train.crops, fronts, nn.BCEWithLogitsLoss(), 1.0, seed, epochs, show_progress, "facing, distilled")
    return FacingResult(net, accuracy(net, held_out), len(train), len(held_out), time.perf_counter() - start,
                        tuple(member.held_out_accuracy for member in trained))


def train_face_turn(train: TurnCrops, held_out: TurnCrops, seed: int, epochs: int = EPOCHS,
                    show_progress: bool = True) -> FaceTurnResult:
    """Train a :class:`FaceTurnNet` on ``train`` and measure it on ``held_out`` (step 3); the same ``seed`` gives
    the same weights on one kind of CPU."""
    if len(train) < BATCH:
        raise ValueError(f"{len(train)} rendered people have their nose and ears labelled; the face turn needs "
                         f"{BATCH} or more")
    start = time.perf_counter()
    torch.manual_seed(seed)
    net = FaceTurnNet()
    _fit(net, train.crops, train.across, nn.MSELoss(), -1.0, seed, epochs, show_progress, "face turn")
    error = profile_sign = None
    if len(held_out):
        read = _outputs(net, held_out.crops)
        error = float(np.abs(read - held_out.across).mean())
        profile = np.abs(held_out.across) >= 0.5
        if profile.any():
            profile_sign = float((np.sign(read[profile]) == np.sign(held_out.across[profile])).mean())
    return FaceTurnResult(net, error, profile_sign, len(train), len(held_out), time.perf_counter() - start)


def moved(crop: np.ndarray, rows: int, columns: int) -> np.ndarray:
    """``crop`` with its content moved down by ``rows`` and right by ``columns`` (negative: up, left), the edges it
    leaves filled with the nearest row or column: the person as a box drawn higher or lower frames them."""
    height, width = crop.shape[:2]
    padded = np.pad(crop, ((abs(rows), abs(rows)), (abs(columns), abs(columns)), (0, 0)), mode="edge")
    top, left = abs(rows) - rows, abs(columns) - columns
    return padded[top:top + height, left:left + width]


def train_head_colours(train: FacingCrops, held_out: FacingCrops, seed: int) -> HeadResult:
    """Train a :class:`HeadColours` on ``train`` and measure it on ``held_out`` (step 4): :data:`HEAD_CROPS` drawn,
    each in :data:`HEAD_LOOKS` camera looks, moved and mirrored; full-batch L-BFGS on the L2-weighted binary
    cross-entropy. The same ``seed`` gives the same weights on one kind of CPU."""
    if len(train) < BATCH:
        raise ValueError(f"{len(train)} rendered people face the camera or away from it; the head reader needs "
                         f"{BATCH} or more")
    start = time.perf_counter()
    rng = np.random.default_rng(seed)
    chosen = rng.choice(len(train), min(HEAD_CROPS, len(train)), replace=False)
    looks = []
    for _ in range(HEAD_LOOKS):
        for crop in train.crops[chosen]:
            look = moved(camera_look(crop, rng), int(rng.integers(-HEAD_SHIFT_ROWS, HEAD_SHIFT_ROWS + 1)),
                         int(rng.integers(-1, 2)))
            looks.append(look[:, ::-1] if rng.random() < 0.5 else look)  # a mirror keeps the front a front
    with torch.no_grad():  # the cells once, not at every L-BFGS evaluation; the crops in batches, not all as floats
        cells = torch.cat([HeadColours.cells(_batch(np.stack(looks[start:start + 1024])))
                           for start in range(0, len(looks), 1024)])
    targets = torch.from_numpy(np.tile(train.front[chosen], HEAD_LOOKS).astype(np.float32))
    torch.manual_seed(seed)
    net = HeadColours()
    optimiser = torch.optim.LBFGS(net.parameters(), max_iter=HEAD_ITERATIONS)

    def loss() -> Tensor:
        optimiser.zero_grad()
        value = (nn.functional.binary_cross_entropy_with_logits(net.logit(cells).squeeze(1), targets)
                 + HEAD_L2 * net.logit.weight.square().sum())
        value.backward()
        return value

    optimiser.step(loss)
    read = _outputs(net, held_out.crops) if len(held_out) else np.zeros(0, np.float32)
    return HeadResult(net, accuracy(net, held_out), ranking(read, held_out.front) if len(held_out) else None,
                      len(chosen), time.perf_counter() - start)
