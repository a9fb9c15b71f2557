window.addEventListener("error",function(){var b=document.body;
b.dataset.scriptErrors=String(Number(b.dataset.scriptErrors||0)+1);});
window.addEventListener("load",function(){var imgs=document.images,ok=0,b=document.body;
for(var i=0;i<imgs.length;i++){if(imgs[i].complete&&imgs[i].naturalWidth>0){ok++;}}
b.dataset.imagesTotal=String(imgs.length);b.dataset.imagesLoaded=String(ok);
var maths=document.getElementsByTagName("math"),laid=0;
for(var j=0;j<maths.length;j++){var r=maths[j].getBoundingClientRect();
if(r.width>0&&r.height>0){laid++;}}
b.dataset.mathTotal=String(maths.length);b.dataset.mathLaidOut=String(laid);});
