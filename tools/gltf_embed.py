#!/usr/bin/env python3
"""Packs a glTF whose buffers and images are files beside it into one file
(Python's standard library only):

  gltf_embed.py IN.gltf OUT.glb    a binary glTF: one BIN chunk holding the
                                   buffers, then each image as a bufferView
                                   with its mimeType
  gltf_embed.py IN.gltf OUT.gltf   the JSON alone: each buffer and image a
                                   data: URI (base64)

The image's mimeType follows its file's extension (.png: image/png, .jpg and
.jpeg: image/jpeg). tests/cli_gltf_embedded.sh renders the three forms of a
model and finds them equal."""
import base64, json, os, struct, sys

MIME = {".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg"}


def read_ref(folder, uri):
    if uri.startswith("data:"):
        return base64.b64decode(uri.split(",", 1)[1])
    with open(os.path.join(folder, uri), "rb") as f:
        return f.read()


def pad4(data, fill=b"\0"):
    return data + fill * (-len(data) % 4)


def to_glb(doc, folder):
    """The buffers one after the other (each from a multiple of 4), then the
    images, as the BIN chunk; bufferViews moved to buffer 0 at their offset."""
    blob, starts = b"", []
    for b in doc.get("buffers", []):
        starts.append(len(blob))
        blob = pad4(blob + read_ref(folder, b["uri"]))
    for v in doc.get("bufferViews", []):
        v["byteOffset"] = v.get("byteOffset", 0) + starts[v.get("buffer", 0)]
        v["buffer"] = 0
    views = doc.setdefault("bufferViews", [])
    for img in doc.get("images", []):
        uri = img.pop("uri")
        data = read_ref(folder, uri)
        img["mimeType"] = MIME[os.path.splitext(uri)[1].lower()]
        img["bufferView"] = len(views)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        blob = pad4(blob + data)
    doc["buffers"] = [{"byteLength": len(blob)}]
    js = pad4(json.dumps(doc, separators=(",", ":")).encode(), b" ")
    chunks = (struct.pack("<II", len(js), 0x4E4F534A) + js +
              struct.pack("<II", len(blob), 0x004E4942) + blob)
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def to_data_uris(doc, folder):
    for b in doc.get("buffers", []):
        b["uri"] = ("data:application/octet-stream;base64," +
                    base64.b64encode(read_ref(folder, b["uri"])).decode())
    for img in doc.get("images", []):
        mime = MIME[os.path.splitext(img["uri"])[1].lower()]
        img["uri"] = ("data:%s;base64," % mime +
                      base64.b64encode(read_ref(folder, img["uri"])).decode())
    return json.dumps(doc).encode()


def main(src, dst):
    with open(src) as f:
        doc = json.load(f)
    folder = os.path.dirname(os.path.abspath(src))
    out = to_glb(doc, folder) if dst.lower().endswith(".glb") else to_data_uris(doc, folder)
    with open(dst, "wb") as f:
        f.write(out)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
