# Copies the front end (static/ and the vendor files of node_modules) to DEST.
# OrbitControls imports the bare name 'three'; it is pointed at the copied module so pages need no
# import map (an inline script, which the server's Content-Security-Policy forbids).
file(REMOVE_RECURSE ${DEST})
file(COPY ${SOURCE}/static/ DESTINATION ${DEST})
set(nm ${SOURCE}/node_modules)
file(COPY ${nm}/three/build/three.module.js ${nm}/three/build/three.core.js
          ${nm}/uplot/dist/uPlot.iife.min.js ${nm}/uplot/dist/uPlot.min.css
     DESTINATION ${DEST}/vendor)
file(READ ${nm}/three/examples/jsm/controls/OrbitControls.js orbit)
string(REPLACE "from 'three';" "from './three.module.js';" orbit "${orbit}")
file(WRITE ${DEST}/vendor/OrbitControls.js "${orbit}")
configure_file(${nm}/three/LICENSE ${DEST}/vendor/three.LICENSE COPYONLY)
configure_file(${nm}/uplot/LICENSE ${DEST}/vendor/uPlot.LICENSE COPYONLY)
