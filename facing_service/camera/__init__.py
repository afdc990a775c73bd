"""The camera front end (an optional extra, ``pip install 'facing-service[camera]'``): people
in front of a camera become the service's input, with no tracker to write. Frames from a
camera, a video or a folder; faces and their landmarks by MediaPipe; each head's pose by a
generic face fitted with the camera's intrinsics; an id per face; poses published as a
tracker would. Beside ``tools/``: only the commands import it, never the service, the core
or the client, so the service's install and container never need its heavy dependencies.

Pure parts (``face_model``, ``intrinsics``, ``face_ids``) need only numpy; ``head_pose`` and
``frames`` need OpenCV, ``landmarks`` MediaPipe: both come with the extra.
"""
