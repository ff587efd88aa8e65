"""The design explorer: a web app over the scene (`taxel explore`).

`controls` names the design variables (scene path, display unit, slider range),
`session` turns a set of control values into a scene and its answer (cached in a
study store; 3D in a background process that a moved control cancels), and `app`
is the trame page that shows them.
"""
